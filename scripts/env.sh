# Sourced by the project's scripts: a ROS environment that does not depend on the caller's shell.
# Debian's ROS 1 lives under /usr; the build must use Debian's python3, not a pyenv one that may come first in PATH.
PKM_ROOT="$(cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/.." && pwd)"
export PKM_WS="${PKM_WS:-$PKM_ROOT/.catkin_ws}"
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:$PATH"
export PYTHONNOUSERSITE=1
unset PYTHONPATH PYENV_VERSION
export ROS_HOME="$PKM_WS/ros_home"
export ROS_LOG_DIR="$PKM_WS/ros_home/log"
export ROSCONSOLE_STDOUT_LINE_BUFFERED=1
export ROS_PYTHON_VERSION=3
