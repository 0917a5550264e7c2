#!/usr/bin/env bash
# Fails if any C++ file of the repository (include/ src/ test/ bench/, *.cpp *.hpp) is not formatted according to
# .clang-format (clang-format --dry-run --Werror), listing the offending files. Fix with: clang-format -i <files>.
# Registered as the ctest test format_check. PKM_FORMAT_VERBOSE=1 shows every violation.
set -euo pipefail
cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/.."
mapfile -t files < <(find include src test bench -type f \( -name '*.cpp' -o -name '*.hpp' \) 2>/dev/null | sort)
if [ ${#files[@]} -eq 0 ]; then
  echo "format_check: no C++ files"
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  if ! out="$(clang-format --dry-run --Werror "$f" 2>&1)"; then
    bad+=("$f")
    if [ "${PKM_FORMAT_VERBOSE:-0}" = 1 ]; then echo "$out" >&2; fi
  fi
done
if [ ${#bad[@]} -eq 0 ]; then
  echo "format_check: ${#files[@]} files formatted according to .clang-format"
  exit 0
fi
echo "format_check: FAILED: ${#bad[@]} of ${#files[@]} files are not formatted according to .clang-format:" >&2
printf '  %s\n' "${bad[@]}" >&2
echo "fix with: clang-format -i ${bad[*]}" >&2
exit 1
