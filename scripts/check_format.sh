#!/usr/bin/env bash
# Fails if any C++ file of the repository (include/ src/ test/ bench/, *.cpp *.hpp) is not formatted according to
# .clang-format. Fix with: clang-format -i <files>. Registered as the ctest test format_check.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mapfile -t files < <(find include src test bench -type f \( -name '*.cpp' -o -name '*.hpp' \) 2>/dev/null | sort)
if [ ${#files[@]} -eq 0 ]; then
  echo "format_check: no C++ files"
  exit 0
fi
if clang-format --dry-run --Werror "${files[@]}"; then
  echo "format_check: ${#files[@]} files formatted according to .clang-format"
else
  echo "format_check: FAILED, run: clang-format -i \$(find include src test bench -name '*.cpp' -o -name '*.hpp')" >&2
  exit 1
fi
