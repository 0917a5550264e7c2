#!/usr/bin/env bash
# scripts/build must refuse a workspace whose src/pkm_accuracy links to another checkout (and say which), and must
# leave that link as it was: a single link to the checkout, or a directory of links to its entries (the layout
# scripts/build makes). Registered as the ctest test workspace_guard. Runs no build: the check comes first.
set -euo pipefail
ROOT="$(cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/ws/src" "$tmp/other"
ln -s "$tmp/other" "$tmp/ws/src/pkm_accuracy"
set +e
out="$(PKM_WS="$tmp/ws" bash "$ROOT/scripts/build" 2>&1)"
rc=$?
set -e
if [ "$rc" -ne 2 ]; then
  echo "workspace_guard: FAILED: scripts/build exited with $rc (expected 2) on a workspace of another checkout:" >&2
  echo "$out" >&2
  exit 1
fi
if ! grep -q "belongs to the checkout $tmp/other" <<<"$out"; then
  echo "workspace_guard: FAILED: the message does not name the other checkout: $out" >&2
  exit 1
fi
if [ "$(readlink "$tmp/ws/src/pkm_accuracy")" != "$tmp/other" ]; then
  echo "workspace_guard: FAILED: the link was changed" >&2
  exit 1
fi
echo "workspace_guard: ok ($out)"
# The same with the directory of links.
mkdir -p "$tmp/ws2/src/pkm_accuracy" "$tmp/other2"
touch "$tmp/other2/package.xml"
ln -s "$tmp/other2/package.xml" "$tmp/ws2/src/pkm_accuracy/package.xml"
set +e
out2="$(PKM_WS="$tmp/ws2" bash "$ROOT/scripts/build" 2>&1)"
rc=$?
set -e
if [ "$rc" -ne 2 ] || ! grep -q "belongs to the checkout $tmp/other2" <<<"$out2"; then
  echo "workspace_guard: FAILED: scripts/build exited with $rc on a workspace linking to another checkout: $out2" >&2
  exit 1
fi
if [ "$(readlink "$tmp/ws2/src/pkm_accuracy/package.xml")" != "$tmp/other2/package.xml" ] ||
  [ -e "$tmp/ws2/src/pkm_accuracy/CMakeLists.txt" ]; then
  echo "workspace_guard: FAILED: the links were changed" >&2
  exit 1
fi
echo "workspace_guard: ok ($out2)"
