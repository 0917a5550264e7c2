#!/usr/bin/env bash
# Fails if any translation unit of the core (src/core/**/*.cpp) depends on a ROS header: each is compiled with
# `g++ -M` using only the repository's include/ and Eigen (no catkin include directories), and every dependency path
# is checked for /ros/, /tf2, /urdf, /actionlib, /catkin and roscpp. A core file that cannot even be preprocessed
# this way fails too. Registered as the ctest test core_is_ros_free.
set -euo pipefail
cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/.."   # relative paths: the repository's own location never matches a pattern
CXX="${CXX:-g++}"
FORBIDDEN='/ros/|/tf2|/urdf|/actionlib|/catkin|roscpp'

mapfile -t sources < <(find src/core -type f -name '*.cpp' 2>/dev/null | sort)
if [ ${#sources[@]} -eq 0 ]; then
  echo "core_is_ros_free: no core sources yet (src/core/**/*.cpp)"
  exit 0
fi
status=0
for src in "${sources[@]}"; do
  if ! deps="$("$CXX" -std=c++17 -Iinclude -I/usr/include/eigen3 -M "$src" 2>&1)"; then
    echo "core_is_ros_free: FAILED: $src does not preprocess with only include/ and Eigen:" >&2
    echo "$deps" >&2
    status=1
    continue
  fi
  bad="$(printf '%s\n' "$deps" | tr -s ' \\' '\n\n' | grep -v ':$' | grep -E "$FORBIDDEN" || true)"
  if [ -n "$bad" ]; then
    echo "core_is_ros_free: FAILED: $src depends on ROS:" >&2
    printf "  %s\n" $bad | head -n 10 >&2 || true
    status=1
  fi
done
if [ $status -eq 0 ]; then echo "core_is_ros_free: ${#sources[@]} core sources, no ROS dependency"; fi
exit $status
