# find_package(catkin [REQUIRED] [COMPONENTS ...]) for a package built by `ddes catkin_make`:
# ddes's catkin (ddes_catkin.cmake), found through CMAKE_PREFIX_PATH.
#
# Sets catkin_INCLUDE_DIRS, catkin_LIBRARIES, catkin_LIBRARY_DIRS, catkin_EXPORTED_TARGETS,
# catkin_DEFINITIONS and, for each component X, X_FOUND, X_INCLUDE_DIRS, X_LIBRARIES, ...; the
# CATKIN_PACKAGE_*_DESTINATION variables; and defines catkin_package(), add_message_files(),
# generate_messages() and the other catkin functions.

if(NOT CATKIN_TOPLEVEL OR NOT DEFINED DDES_CATKIN_DIR)
  message(FATAL_ERROR
    "ddes's catkin (${CMAKE_CURRENT_LIST_DIR}) builds whole workspaces: run `ddes catkin_make` "
    "in the workspace (the folder holding src/) rather than CMake on this package alone")
endif()
if(CATKIN_FIND_COMPONENTS OR CATKIN_FIND_REQUIRED OR CATKIN_FIND_QUIETLY)
  message(FATAL_ERROR "find_package() only supports lower-case package name 'catkin'")
endif()
include("${CMAKE_CURRENT_LIST_DIR}/ddes_catkin.cmake")
_ddes_catkin_find()
