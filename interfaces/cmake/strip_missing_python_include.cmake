# Work-around for ROS 2 message packages installed from PyPI wheels.
#
# Their exported `*__rosidl_generator_py` targets list the Python include directory of the
# machine that built the wheels (e.g. /opt/python/cp311-cp311/include/python3.11). That path
# does not exist here and CMake's generate step rejects it. Drop every non-existent entry from
# the imported targets of this directory. On a regular ROS install all entries exist, so this
# changes nothing there. Including this file applies it to the including package, after its
# rosidl_generate_interfaces() (each package includes it OPTIONAL: copied alone, it builds
# without).
function(turtle_traj_strip_missing_include_dirs)
  get_property(_targets DIRECTORY PROPERTY IMPORTED_TARGETS)
  foreach(_target IN LISTS _targets)
    get_target_property(_dirs ${_target} INTERFACE_INCLUDE_DIRECTORIES)
    if(NOT _dirs)
      continue()
    endif()
    set(_kept "")
    foreach(_dir IN LISTS _dirs)
      if(_dir MATCHES "^\\$<" OR EXISTS "${_dir}")
        list(APPEND _kept "${_dir}")
      endif()
    endforeach()
    set_target_properties(${_target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_kept}")
  endforeach()
endfunction()

turtle_traj_strip_missing_include_dirs()
