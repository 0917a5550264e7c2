#!/usr/bin/env bash
# The install space on its own (ctest install_space; needs a built workspace, scripts/build):
#   1. installs the package into a temporary directory (DESTDIR=TMP/stage cmake --install <build>: the files land in
#      TMP/stage<prefix>, <prefix> being the build's CMAKE_INSTALL_PREFIX, which catkin writes into the installed
#      setup.sh, pkm_accuracyConfig.cmake and pkm_accuracy.pc);
#   2. checks that no installed file, text or binary (RPATHs included), and no installed link's target names the
#      checkout (source, build or devel space) other than through <prefix>;
#   3. from then on runs in a clean environment that sources only <prefix>/setup.bash, in a private mount namespace
#      where an empty directory hides the checkout and the staged install is mounted at <prefix> (when unshare can
#      make one; otherwise the staged install runs where it is, its setup.bash finding its own location, and the
#      package built against it is skipped: said in the output):
#      - rospack finds the package in the install space; pkm_verify --version, and pkm_verify on the installed
#        config/ref6.yaml (workspace paper_40deg: UNSAFE, exit status 1);
#      - roscore + roslaunch pkm_accuracy accuracy_checker.launch (the installed launch, robot and node); ~describe
#        answers (version, the named workspaces); /verify_workspace on `workspace: paper_40deg` answers UNSAFE;
#      - rosrun pkm_accuracy planner_example.py (the Python example, service and action: executes, exit 0) and
#        rosrun pkm_accuracy planner_client_example _mode:=trajectory (the C++ example: executes, exit 0);
#      - a catkin package built against the install space (find_package(catkin COMPONENTS pkm_accuracy)) that
#        links the three exported libraries (core, io, ros: RobotLoader) and runs; the installed examples/upu3 (a
#        user's own robot type) built against it, and pkm_verify --plugin running it.
# Environment: PKM_WS (workspace, default .catkin_ws of this checkout), PKM_JOBS (jobs of the consumer build, 1).
set -euo pipefail

if [ "${1:-}" = "--inside" ]; then
  # ---- stage 3, in a clean environment: $2 = prefix, $3 = scratch directory, $4 = build a package against it ----
  PREFIX="$2"
  SCRATCH="$3"
  CONSUMER="$4"
  cd "$SCRATCH"
  export ROS_HOME="$SCRATCH/ros_home" ROS_LOG_DIR="$SCRATCH/ros_home/log" ROSCONSOLE_STDOUT_LINE_BUFFERED=1
  export ROS_PYTHON_VERSION=3 PYTHONNOUSERSITE=1
  set +u  # catkin's setup files read unset variables
  source "$PREFIX/setup.bash"
  set -u
  say() { echo "install_space: $*"; }
  fail() {
    echo "install_space: FAILED: $*" >&2
    exit 1
  }

  found="$(rospack find pkm_accuracy)"
  [ "$found" = "$PREFIX/share/pkm_accuracy" ] || fail "rospack find pkm_accuracy gives $found, not $PREFIX/share/pkm_accuracy"
  say "rospack find pkm_accuracy: $found"
  version="$(rosrun pkm_accuracy pkm_verify --version)"
  say "pkm_verify --version: $version"
  status=0
  rosrun pkm_accuracy pkm_verify --robot "$found/config/ref6.yaml" --workspace paper_40deg \
    --thresholds 1e-4,1e-4,1e-4,1e-3,1e-3,1e-3 --quiet >"$SCRATCH/pkm_verify.out" 2>&1 || status=$?
  [ "$status" = 1 ] || fail "pkm_verify on paper_40deg: exit status $status, expected 1 (UNSAFE): $(cat "$SCRATCH/pkm_verify.out")"
  say "pkm_verify --robot <installed>/config/ref6.yaml --workspace paper_40deg: UNSAFE (exit status 1)"

  PORT="$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
  export ROS_MASTER_URI="http://127.0.0.1:$PORT" ROS_HOSTNAME=127.0.0.1
  set -m  # roscore / roslaunch in their own process groups
  roscore -p "$PORT" >"$SCRATCH/roscore.log" 2>&1 &
  CORE=$!
  LAUNCH=""
  stop() {
    for pid in $LAUNCH $CORE; do
      kill -INT "$pid" 2>/dev/null || true
      for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
      kill -TERM -- "-$pid" 2>/dev/null || true
    done
  }
  trap stop EXIT
  for _ in $(seq 150); do rosparam list >/dev/null 2>&1 && break; sleep 0.2; done
  roslaunch pkm_accuracy accuracy_checker.launch >"$SCRATCH/roslaunch.log" 2>&1 &
  LAUNCH=$!
  for _ in $(seq 150); do rosservice info /pkm_accuracy/describe >/dev/null 2>&1 && break; sleep 0.2; done
  describe="$(rosservice call /pkm_accuracy/describe)" || fail "~describe: no answer; roslaunch: $(cat "$SCRATCH/roslaunch.log")"
  grep -q '^success: True' <<<"$describe" || fail "~describe: $describe"
  [ "$(sed -n '/^workspaces:/,$p' <<<"$describe" | tr -d ' \n')" = "workspaces:-paper-paper_40deg" ] ||
    fail "~describe does not list the named workspaces paper, paper_40deg: $describe"
  grep -q "^version: \"*${version##* }\"*$" <<<"$describe" || fail "~describe's version is not ${version##* }: $describe"
  say "roslaunch pkm_accuracy accuracy_checker.launch; ~describe: success, version ${version##* }, workspaces [paper, paper_40deg]"
  answer="$(rosservice call /verify_workspace \
    "{workspace: paper_40deg, thresholds: [1.0e-4, 1.0e-4, 1.0e-4, 1.0e-3, 1.0e-3, 1.0e-3], time_budget: 30.0}")"
  grep -q '^verdict: "*UNSAFE"*$' <<<"$answer" || fail "/verify_workspace on paper_40deg: $answer"
  say "/verify_workspace {workspace: paper_40deg}: UNSAFE"
  rosrun pkm_accuracy planner_example.py >"$SCRATCH/planner_example.log" 2>&1 ||
    fail "planner_example.py: exit status $?: $(cat "$SCRATCH/planner_example.log")"
  grep -q "planner: executing" "$SCRATCH/planner_example.log" || fail "planner_example.py: $(cat "$SCRATCH/planner_example.log")"
  say "rosrun pkm_accuracy planner_example.py: executing (exit status 0)"
  rosrun pkm_accuracy planner_client_example _mode:=trajectory >"$SCRATCH/planner_client_example.log" 2>&1 ||
    fail "planner_client_example: exit status $?: $(cat "$SCRATCH/planner_client_example.log")"
  say "rosrun pkm_accuracy planner_client_example _mode:=trajectory: executing (exit status 0)"

  if [ "$CONSUMER" != yes ]; then
    say "the package built against the install space: skipped (the install space is not at its prefix)"
    exit 0
  fi
  # A package built against the install space: the exported include directories and the three libraries.
  mkdir -p "$SCRATCH/consumer_ws/src/pkm_consumer"
  cd "$SCRATCH/consumer_ws/src/pkm_consumer"
  cat >package.xml <<'EOF'
<?xml version="1.0"?>
<package format="2">
  <name>pkm_consumer</name>
  <version>0.0.1</version>
  <description>Builds against an installed pkm_accuracy.</description>
  <maintainer email="nobody@example.org">nobody</maintainer>
  <license>BSD-3-Clause</license>
  <buildtool_depend>catkin</buildtool_depend>
  <depend>pkm_accuracy</depend>
  <depend>roscpp</depend>
</package>
EOF
  cat >CMakeLists.txt <<'EOF'
cmake_minimum_required(VERSION 3.16)
project(pkm_consumer CXX)
set(CMAKE_CXX_STANDARD 17)
find_package(catkin REQUIRED COMPONENTS pkm_accuracy roscpp)
catkin_package()
include_directories(${catkin_INCLUDE_DIRS})
add_executable(consumer consumer.cpp)
target_link_libraries(consumer ${catkin_LIBRARIES})
EOF
  cat >consumer.cpp <<'EOF'
// Uses one function of each exported library: the core (the model), io (the robot file) and ros (RobotLoader).
#include <iostream>
#include "pkm_accuracy/core/Version.hpp"
#include "pkm_accuracy/core/model/GoughPlatform.hpp"
#include "pkm_accuracy/io/RobotFile.hpp"
#include "pkm_accuracy/ros/RobotLoader.hpp"
int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const pkm_accuracy::io::RobotFile file = pkm_accuracy::io::loadRobotFile(argv[1]);
  const pkm_accuracy::model::GoughPlatform robot(file.geometry);
  pkm_accuracy::DVec pose(6);
  pose << 0.0, 0.0, 0.475, 0.0, 0.0, 0.0;
  std::cout << "version " << pkm_accuracy::version() << ", " << file.workspaces.size() << " workspaces, "
            << pkm_accuracy::ros_layer::formatAnchorName("base_anchor_%d", 3) << ", worst dx at the centre "
            << robot.worstErrorAt(pose)[0] << " m" << std::endl;
  return 0;
}
EOF
  cd "$SCRATCH/consumer_ws"
  catkin_make -j"${PKM_JOBS:-1}" -DPYTHON_EXECUTABLE=/usr/bin/python3 >"$SCRATCH/consumer_build.log" 2>&1 ||
    fail "the package built against the install space does not build: $(tail -30 "$SCRATCH/consumer_build.log")"
  out="$("$SCRATCH/consumer_ws/devel/lib/pkm_consumer/consumer" "$found/config/ref6.yaml")" ||
    fail "the package built against the install space does not run: $out"
  grep -q "^version ${version##* }, 2 workspaces, base_anchor_3, worst dx at the centre [0-9]" <<<"$out" ||
    fail "the package built against the install space: $out"
  say "a package built against the install space (core, io, ros libraries): $out"

  # The installed example of a user's own robot type, built against the install space and run by pkm_verify.
  cp -r "$found/examples/upu3" "$SCRATCH/upu3"
  mkdir "$SCRATCH/upu3/build"
  cd "$SCRATCH/upu3/build"
  { cmake .. && make -j"${PKM_JOBS:-1}"; } >"$SCRATCH/upu3_build.log" 2>&1 ||
    fail "the installed example examples/upu3 does not build: $(tail -30 "$SCRATCH/upu3_build.log")"
  rosrun pkm_accuracy pkm_verify --plugin "$SCRATCH/upu3/build/libupu3_plugin.so" --robot "$SCRATCH/upu3/upu3.yaml" \
    --mode max-error --quiet >"$SCRATCH/upu3.out" 2>&1 || fail "pkm_verify --plugin libupu3_plugin.so: $(cat "$SCRATCH/upu3.out")"
  say "the installed examples/upu3 built against the install space and run by pkm_verify --plugin: exit status 0"
  exit 0
fi

# ---- stages 1 and 2 ----
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
ROOT="$(readlink -f "$PKM_ROOT")"
WS="$(readlink -f "$PKM_WS")"
# What is hidden in stage 3: the checkout, and the workspace (build and devel spaces) if it lies elsewhere.
HIDE=("$ROOT")
case "$WS/" in "$ROOT"/*) ;; *) HIDE+=("$WS") ;; esac
BUILD="$PKM_WS/build"
[ -f "$BUILD/cmake_install.cmake" ] || {
  echo "install_space: no build in $BUILD (run scripts/build first)" >&2
  exit 2
}
SCRATCH="$(mktemp -d /tmp/pkm_install_space.XXXXXX)"
trap 'rm -rf "$SCRATCH"' EXIT
PREFIX="$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$BUILD/CMakeCache.txt")"
STAGED="$SCRATCH/stage$PREFIX"
DESTDIR="$SCRATCH/stage" cmake --install "$BUILD" >"$SCRATCH/install.log" || {
  cat "$SCRATCH/install.log" >&2
  exit 1
}
echo "install_space: installed into $STAGED ($(find "$STAGED" -type f | wc -l) files; prefix $PREFIX)"
outside="$(find "$SCRATCH/stage" -type f | grep -v "^$STAGED/" || true)"
[ -z "$outside" ] || {
  echo "install_space: FAILED: files installed outside the prefix $PREFIX:" >&2
  sed "s|^|  |" <<<"$outside" >&2
  exit 1
}
for f in lib/pkm_accuracy/accuracy_checker lib/pkm_accuracy/planner_client_example lib/pkm_accuracy/pkm_verify \
  lib/pkm_accuracy/planner_example.py lib/libpkm_accuracy_core.so lib/libpkm_accuracy_io.so \
  lib/libpkm_accuracy_ros.so include/pkm_accuracy/ros/RobotLoader.hpp include/pkm_accuracy/VerifyWorkspace.h \
  share/pkm_accuracy/package.xml share/pkm_accuracy/launch/accuracy_checker.launch share/pkm_accuracy/config/ref6.yaml \
  share/pkm_accuracy/urdf/ref6.urdf share/pkm_accuracy/rviz/pkm_accuracy.rviz share/pkm_accuracy/examples/upu3/upu3.yaml \
  setup.bash; do
  [ -e "$STAGED/$f" ] || {
    echo "install_space: FAILED: $f is not installed" >&2
    exit 1
  }
done
# Every mention of the checkout must be the prefix itself (catkin's generated files name it), in the files and in the
# targets of installed links (install() copies a link as a link: a link into the checkout works until the checkout is
# gone); a relative link must stay inside the install space. Not counted: the bytecode of the generated Python messages
# (genmsg's install step byte-compiles them in the devel space and installs the caches, which record the devel file
# names for tracebacks; the modules load from the installed sources).
hits="$(/usr/bin/python3 - "$STAGED" "$PREFIX" "$ROOT" "$PKM_ROOT" "$WS" "$PKM_WS" <<'PY'
import os, sys
staged, prefix, roots = sys.argv[1], sys.argv[2].encode(), {r.encode() for r in sys.argv[3:]}
for d, dirs, files in os.walk(staged):
    for f in files + [x for x in dirs if os.path.islink(os.path.join(d, x))]:
        path = os.path.join(d, f)
        if os.path.islink(path):
            target = os.readlink(path)
            inside = os.path.normpath(os.path.join(d, target)).startswith(staged + os.sep)
            if any(r in target.encode().replace(prefix, b"") for r in roots) or not (os.path.isabs(target) or inside):
                print(os.path.relpath(path, staged) + " -> " + target)
            continue
        if os.path.basename(d) == "__pycache__" and f.endswith(".pyc"):
            continue
        data = open(path, "rb").read().replace(prefix, b"")
        if any(r in data for r in roots):
            print(os.path.relpath(path, staged))
PY
)"
if [ -n "$hits" ]; then
  echo "install_space: FAILED: installed files or links name the checkout $ROOT or the workspace $WS (other than the" \
    "prefix $PREFIX):" >&2
  sed "s|^|  |" <<<"$hits" >&2
  exit 1
fi
echo "install_space: no installed file or link names the checkout or the workspace (other than the prefix)"

cp "${BASH_SOURCE[0]}" "$SCRATCH/check.sh"
cd "$SCRATCH"
clean=(env -i HOME="$SCRATCH" PATH=/usr/bin:/bin PKM_JOBS="${PKM_JOBS:-1}" bash --noprofile --norc "$SCRATCH/check.sh"
  --inside)
unshare_args=(--mount)
[ "$(id -u)" = 0 ] || unshare_args+=(--map-root-user)
# In the namespace: an empty directory over the checkout (and the workspace), then the staged install at its prefix.
mounts=""
for d in "${HIDE[@]}"; do mounts+="mount -t tmpfs -o size=1m pkm_hidden '$d' && "; done
mounts+="mkdir -p '$PREFIX' && mount --bind '$STAGED' '$PREFIX'"
if unshare "${unshare_args[@]}" sh -c "$mounts" 2>/dev/null; then
  echo "install_space: running with ${HIDE[*]} hidden and the install space at its prefix (private mount" \
    "namespace)"
  unshare "${unshare_args[@]}" sh -c "$mounts && exec \"\$@\"" sh "${clean[@]}" "$PREFIX" "$SCRATCH" yes
else
  echo "install_space: unshare cannot make a private mount namespace here: running the staged install where it is," \
    "with the checkout visible (the clean environment sources only its setup.bash)"
  "${clean[@]}" "$STAGED" "$SCRATCH" no
fi
echo "install_space: OK"
