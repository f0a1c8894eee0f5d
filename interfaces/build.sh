#!/usr/bin/env bash
# Build the interface packages with plain cmake and install them into a Python venv prefix.
#
# Usage: interfaces/build.sh VENV
# colcon users do not need this: `colcon build --base-paths interfaces` builds the same packages.
set -euo pipefail

venv=$(cd "${1:?usage: build.sh VENV}" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
build_root="$venv/build/interfaces"
mkdir -p "$build_root"
python="$venv/bin/python"
site_packages=$("$python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')

# Programs of the venv must find the ament index without the user exporting anything: a .pth
# file puts the venv in front of AMENT_PREFIX_PATH at interpreter start, keeping any sourced
# ROS install behind it.
cat > "$site_packages/turtle_traj_ament_prefix.pth" <<PTH
import os, sys; _p = [p for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]; sys.prefix in _p or os.environ.__setitem__('AMENT_PREFIX_PATH', os.pathsep.join([sys.prefix] + _p))
PTH

installed_elsewhere() {
  # True when another prefix on AMENT_PREFIX_PATH (a sourced ROS install) already has $1.
  local prefix
  IFS=: read -ra prefixes <<< "${AMENT_PREFIX_PATH:-}"
  for prefix in "${prefixes[@]}"; do
    [ -n "$prefix" ] && [ "$(cd "$prefix" 2>/dev/null && pwd)" != "$venv" ] \
      && [ -e "$prefix/share/ament_index/resource_index/packages/$1" ] && return 0
  done
  return 1
}

export CMAKE_PREFIX_PATH="$venv${CMAKE_PREFIX_PATH:+:$CMAKE_PREFIX_PATH}"
export AMENT_PREFIX_PATH="$venv${AMENT_PREFIX_PATH:+:$AMENT_PREFIX_PATH}"
export PATH="$venv/bin:$PATH"

build_package() {
  local package=$1 log="$build_root.$1.log"
  cmake -S "$here/$package" -B "$build_root/$package" -Wno-dev \
    -DCMAKE_INSTALL_PREFIX="$venv" -DBUILD_TESTING=OFF \
    -DPython3_EXECUTABLE="$python" -DCMAKE_BUILD_TYPE=Release > "$log" 2>&1 \
    && cmake --build "$build_root/$package" -j "$(nproc)" >> "$log" 2>&1 \
    && cmake --install "$build_root/$package" >> "$log" 2>&1 \
    || { echo "interfaces: building $package failed; the end of $log:" >&2
         tail -n 40 "$log" >&2; return 1; }
}

# The packages are independent: build them side by side (most of the time goes into rosidl's
# single-threaded Python generators, so parallel builds fill the cores better than one).
# turtlesim and nav2_msgs are subsets of ROS packages: a sourced ROS install's own are used.
pids=()
for package in turtlesim nav2_msgs turtle_traj_interfaces; do
  if [ "$package" != turtle_traj_interfaces ] && installed_elsewhere "$package"; then
    echo "interfaces: using the installed $package package, not building ours"
    continue
  fi
  echo "interfaces: building $package"
  build_package "$package" &
  pids+=($!)
done
status=0
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
exit $status
