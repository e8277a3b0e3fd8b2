# ddes's catkin: what a ROS package's CMakeLists.txt calls, for C++ nodes built against ddes's
# roscpp (docs/roscpp.md, "Building with catkin").
#
# Provided: find_package(catkin [REQUIRED] [COMPONENTS ...]) (catkinConfig.cmake) setting
# catkin_INCLUDE_DIRS, catkin_LIBRARIES, catkin_LIBRARY_DIRS, catkin_EXPORTED_TARGETS and
# catkin_DEFINITIONS; catkin_package(); add_message_files(), add_service_files(),
# add_action_files() and generate_messages() (headers by ddes's gencpp); catkin_install_python();
# add_rostest() and catkin_add_gtest() (noted: ddes runs rostests itself); the CATKIN_* install
# destinations; CATKIN_DEVEL_PREFIX; ROS_PACKAGE_NAME defined for each package's sources.
#
# The Python side (ddes/roscpp/catkin.py, run as "${DDES_PYTHON}" -m ddes.roscpp.catkin) finds
# and orders the workspace's packages, knows the components, and runs the message generator.

include_guard(GLOBAL)

set(DDES_CATKIN_VERSION "0.8.10")

# -- the workspace (called once, by toplevel/CMakeLists.txt) -------------------------------------
macro(_ddes_catkin_workspace)
  get_filename_component(CATKIN_SOURCE_SPACE "${CATKIN_SOURCE_SPACE}" ABSOLUTE)
  get_filename_component(CATKIN_DEVEL_PREFIX "${CATKIN_DEVEL_PREFIX}" ABSOLUTE)
  set(CATKIN_DEVEL_PREFIX "${CATKIN_DEVEL_PREFIX}" CACHE PATH "catkin devel space" FORCE)
  set(CATKIN_BUILD_PREFIX "${CMAKE_BINARY_DIR}")
  set(DDES_CATKIN_BUILD_DIR "${CMAKE_BINARY_DIR}/ddes_catkin")
  set(DDES_GENCPP_INCLUDE_DIR "${CMAKE_BINARY_DIR}/ddes_gencpp/include")
  if(NOT DEFINED DDES_ROSCPP_SOURCE_DIR OR "${DDES_ROSCPP_SOURCE_DIR}" STREQUAL "")
    get_filename_component(DDES_ROSCPP_SOURCE_DIR "${DDES_CATKIN_DIR}/../cpp" ABSOLUTE)
  endif()
  if(NOT DEFINED PYTHON_EXECUTABLE)
    set(PYTHON_EXECUTABLE "${DDES_PYTHON}")
  endif()
  file(MAKE_DIRECTORY "${CATKIN_DEVEL_PREFIX}/include" "${CATKIN_DEVEL_PREFIX}/lib"
       "${DDES_GENCPP_INCLUDE_DIR}")

  message(STATUS "Using CATKIN_DEVEL_PREFIX: ${CATKIN_DEVEL_PREFIX}")
  message(STATUS "Using CMAKE_PREFIX_PATH: ${CMAKE_PREFIX_PATH}")
  message(STATUS "Using PYTHON_EXECUTABLE: ${DDES_PYTHON}")

  # The packages, their order and the components: from the Python side, at every configure.
  execute_process(
    COMMAND "${DDES_PYTHON}" -m ddes.roscpp.catkin scan
            --source "${CATKIN_SOURCE_SPACE}" --build "${CMAKE_BINARY_DIR}"
            --devel "${CATKIN_DEVEL_PREFIX}" --cmake-dir "${DDES_CATKIN_DIR}"
            --whitelist "${CATKIN_WHITELIST_PACKAGES}" --blacklist "${CATKIN_BLACKLIST_PACKAGES}"
    RESULT_VARIABLE _ddes_rc
    OUTPUT_VARIABLE _ddes_out
    ERROR_VARIABLE _ddes_err
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_STRIP_TRAILING_WHITESPACE)
  if(NOT _ddes_rc EQUAL 0)
    message(FATAL_ERROR "${_ddes_err}")
  endif()
  if(NOT "${_ddes_out}" STREQUAL "")
    message(STATUS "${_ddes_out}")
  endif()
  include("${DDES_CATKIN_BUILD_DIR}/workspace.cmake")
  # an edited package.xml (a new dependency) configures again at the next make
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${DDES_WS_MANIFESTS})
  set_property(GLOBAL PROPERTY DDES_GENCPP_DONE ${DDES_GENCPP_PREGENERATED})

  # Workspace packages' configs (devel/share) and ddes's component configs come first.
  list(PREPEND CMAKE_PREFIX_PATH "${CATKIN_DEVEL_PREFIX}" "${DDES_CATKIN_BUILD_DIR}")
  list(REMOVE_DUPLICATES CMAKE_PREFIX_PATH)

  # catkin's global destinations (the install space layout)
  set(CATKIN_GLOBAL_BIN_DESTINATION bin)
  set(CATKIN_GLOBAL_ETC_DESTINATION etc)
  set(CATKIN_GLOBAL_INCLUDE_DESTINATION include)
  set(CATKIN_GLOBAL_LIB_DESTINATION lib)
  set(CATKIN_GLOBAL_LIBEXEC_DESTINATION lib)
  set(CATKIN_GLOBAL_PYTHON_DESTINATION lib/python3/dist-packages)
  set(CATKIN_GLOBAL_SHARE_DESTINATION share)
  set(CATKIN_PACKAGE_PREFIX "")

  # C++17 unless the user chose: a flag that comes first on the compile line, so a package's
  # add_compile_options(-std=c++11) or CMAKE_CXX_STANDARD still decides for its own sources.
  if(NOT DEFINED CMAKE_CXX_STANDARD AND NOT "${CMAKE_CXX_FLAGS}" MATCHES "-std=")
    if(NOT DEFINED CMAKE_CXX_STANDARD_COMPUTED_DEFAULT
       OR CMAKE_CXX_STANDARD_COMPUTED_DEFAULT LESS 17
       OR CMAKE_CXX_STANDARD_COMPUTED_DEFAULT GREATER_EQUAL 98)
      string(PREPEND CMAKE_CXX_FLAGS "-std=gnu++17 ")
    endif()
  endif()

  option(CATKIN_ENABLE_TESTING "Catkin enable testing" ON)
  message(STATUS "Using CATKIN_ENABLE_TESTING: ${CATKIN_ENABLE_TESTING}")
  if(CATKIN_ENABLE_TESTING)
    enable_testing()
  endif()
  if(NOT TARGET tests)
    add_custom_target(tests)
  endif()
  if(NOT TARGET run_tests)
    add_custom_target(run_tests
      COMMAND "${CMAKE_COMMAND}" -E echo
              "ddes: run rostests with `ddes rostest PKG FILE` (on simulated time)"
      VERBATIM)
  endif()

  set(THREADS_PREFER_PTHREAD_FLAG ON)
  find_package(Threads REQUIRED)
  message(STATUS "catkin ${DDES_CATKIN_VERSION} (ddes ${DDES_VERSION}: C++ nodes build against ddes's roscpp)")

  # ddes's roscpp: built once for this machine into DDES_ROSCPP_CACHE_DIR when a package first
  # asks for it (_ddes_roscpp_library), else once for the whole build space (only if a package
  # links it). Static and position independent (a package's shared library may link it).
  set(DDES_ROSCPP_BINARY_DIR "${CMAKE_BINARY_DIR}/ddes_roscpp")
  set_property(GLOBAL PROPERTY DDES_ROSCPP_LIBRARY_DIR "${DDES_ROSCPP_BINARY_DIR}")
  set(DDES_ROSCPP_INCLUDE_DIR "${DDES_ROSCPP_SOURCE_DIR}/include")
  set(DDES_ROSCPP_SOURCES "${DDES_ROSCPP_SOURCES}")  # (a -D of catkin_make: a change configures again)
  if(NOT DDES_ROSCPP_CACHE_DIR AND EXISTS "${DDES_ROSCPP_SOURCE_DIR}/CMakeLists.txt")
    set(BUILD_SHARED_LIBS OFF)
    set(CMAKE_POSITION_INDEPENDENT_CODE ON)
    add_subdirectory("${DDES_ROSCPP_SOURCE_DIR}" "${DDES_ROSCPP_BINARY_DIR}" EXCLUDE_FROM_ALL)
    unset(CMAKE_POSITION_INDEPENDENT_CODE)
    unset(BUILD_SHARED_LIBS)
    if(NOT TARGET ddes_roscpp)
      message(FATAL_ERROR "ddes's roscpp sources (${DDES_ROSCPP_SOURCE_DIR}) define no target "
                          "'ddes_roscpp': this ddes installation is broken; reinstall ddes")
    endif()
  endif()
  # A package's own libraries are static by default, so every executable holds exactly one copy
  # of ddes's roscpp (its connection to the world); catkin's default is shared.
  option(BUILD_SHARED_LIBS "Build dynamically-linked binaries" OFF)
  message(STATUS "BUILD_SHARED_LIBS is ${BUILD_SHARED_LIBS}")

  list(LENGTH DDES_WS_PACKAGES _ddes_count)
  message(STATUS "~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~")
  message(STATUS "~~  traversing ${_ddes_count} packages in topological order:")
  foreach(_ddes_pkg ${DDES_WS_PACKAGES})
    message(STATUS "~~  - ${_ddes_pkg}")
  endforeach()
  message(STATUS "~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~")
  foreach(_ddes_pkg ${DDES_WS_PACKAGES})
    message(STATUS "+++ processing catkin package: '${_ddes_pkg}'")
    message(STATUS "==> add_subdirectory(${DDES_WS_${_ddes_pkg}_REL})")
    set(_DDES_CURRENT_PACKAGE "${_ddes_pkg}")
    # the subdirectory starts with these definitions (roscpp's ROS_PACKAGE_NAME)
    set_property(DIRECTORY PROPERTY COMPILE_DEFINITIONS "ROS_PACKAGE_NAME=\"${_ddes_pkg}\"")
    add_subdirectory("${DDES_WS_${_ddes_pkg}_PATH}" "${CMAKE_BINARY_DIR}/${DDES_WS_${_ddes_pkg}_REL}")
    set_property(DIRECTORY PROPERTY COMPILE_DEFINITIONS "")
    set_property(GLOBAL PROPERTY DDES_PKG_${_ddes_pkg}_CONFIGURED TRUE)
    get_property(_ddes_called GLOBAL PROPERTY DDES_PKG_${_ddes_pkg}_CATKIN_PACKAGE)
    if(NOT _ddes_called)
      message(WARNING "package '${_ddes_pkg}' (${DDES_WS_${_ddes_pkg}_PATH}/CMakeLists.txt) "
                      "never calls catkin_package(): its executables are built in "
                      "${CMAKE_BINARY_DIR}/${DDES_WS_${_ddes_pkg}_REL}, not in "
                      "devel/lib/${_ddes_pkg} where rosrun and roslaunch look. Call "
                      "catkin_package() after find_package(catkin ...) and before "
                      "add_executable().")
    endif()
  endforeach()
  unset(_DDES_CURRENT_PACKAGE)
endmacro()

# -- components ----------------------------------------------------------------------------------
# A component is a package a package asks for: find_package(catkin COMPONENTS X) or
# find_package(X). _ddes_component_kind sets <out> to ws, library, noop, messages or unknown.
function(_ddes_component_kind name out)
  if(name IN_LIST DDES_WS_PACKAGES)
    set(${out} ws PARENT_SCOPE)
  elseif(name IN_LIST DDES_LIBRARY_COMPONENTS)
    set(${out} library PARENT_SCOPE)
  elseif(name IN_LIST DDES_NOOP_COMPONENTS)
    set(${out} noop PARENT_SCOPE)
  elseif(name IN_LIST DDES_MESSAGE_PACKAGES)
    set(${out} messages PARENT_SCOPE)
  else()
    set(${out} unknown PARENT_SCOPE)
  endif()
endfunction()

# ddes's roscpp built for this machine (once, by the Python side, under a lock), imported here
# from the file CMake's export() wrote for it, for every package of the workspace.
function(_ddes_roscpp_library)
  if(TARGET ddes_roscpp OR NOT DDES_ROSCPP_CACHE_DIR)
    return()
  endif()
  set(_result "${DDES_CATKIN_BUILD_DIR}/roscpp_library.txt")
  file(REMOVE "${_result}")
  execute_process(
    COMMAND "${DDES_PYTHON}" -m ddes.roscpp.catkin library
            --cache-dir "${DDES_ROSCPP_CACHE_DIR}" --cmake "${CMAKE_COMMAND}"
            --compiler "${CMAKE_CXX_COMPILER}"
            --result "${_result}"
            "--define=-DCMAKE_CXX_FLAGS=$CACHE{CMAKE_CXX_FLAGS}"
            "--define=-DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE}"
    RESULT_VARIABLE _rc ERROR_VARIABLE _err ERROR_STRIP_TRAILING_WHITESPACE)
  if(NOT _rc EQUAL 0 OR NOT EXISTS "${_result}")
    message(FATAL_ERROR "${_err}")
  endif()
  file(READ "${_result}" _targets)
  include("${_targets}")
  set_target_properties(ddes_roscpp PROPERTIES IMPORTED_GLOBAL TRUE)
  get_filename_component(_dir "${_targets}" DIRECTORY)
  set_property(GLOBAL PROPERTY DDES_ROSCPP_LIBRARY_DIR "${_dir}/roscpp")
  message(STATUS "Using ddes's roscpp built for this machine (sources ${DDES_ROSCPP_SOURCES}): "
                 "${_dir}/roscpp")
endfunction()

# Headers of a message package of ddes's registry, written once per configure.
function(_ddes_gencpp_bundled)
  get_property(_done GLOBAL PROPERTY DDES_GENCPP_DONE)
  set(_todo "")
  foreach(pkg ${ARGN})
    if(NOT pkg IN_LIST _done AND pkg IN_LIST DDES_MESSAGE_PACKAGES)
      list(APPEND _todo --package "${pkg}")
      set_property(GLOBAL APPEND PROPERTY DDES_GENCPP_DONE "${pkg}")
    endif()
  endforeach()
  if(_todo)
    execute_process(
      COMMAND "${DDES_PYTHON}" -m ddes.roscpp.gencpp --out "${DDES_GENCPP_INCLUDE_DIR}" ${_todo}
      RESULT_VARIABLE _rc ERROR_VARIABLE _err ERROR_STRIP_TRAILING_WHITESPACE)
    if(NOT _rc EQUAL 0)
      message(FATAL_ERROR "generating message headers (${_todo}) failed:\n${_err}")
    endif()
  endif()
endfunction()

# What is exported by the bundled message package `pkg`: the targets real catkin lists (made
# empty here, as catkin does for installed packages).
function(_ddes_dummy_targets pkg)
  foreach(suffix generate_messages_cpp generate_messages_py generate_messages_eus
                 generate_messages_lisp generate_messages_nodejs gencpp)
    if(NOT TARGET ${pkg}_${suffix})
      add_custom_target(${pkg}_${suffix})
    endif()
  endforeach()
endfunction()

# Resolve `names` (and what workspace packages among them depend on) into
# <prefix>_INCLUDE_DIRS/_LIBRARIES/_LIBRARY_DIRS/_EXPORTED_TARGETS, and <name>_FOUND and
# <name>_INCLUDE_DIRS/... for each name, in the caller's scope.  `required`: an unknown name
# stops the configuration with what to do; otherwise its <name>_FOUND is FALSE.
function(_ddes_resolve prefix required)
  set(_inc "${CATKIN_DEVEL_PREFIX}/include")
  set(_libs "")
  set(_libdirs "")
  set(_targets "")
  set(_seen "")
  set(_queue ${ARGN})
  set(_all_found TRUE)
  if(DEFINED _DDES_CURRENT_PACKAGE)
    set(_who "package '${_DDES_CURRENT_PACKAGE}' (${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt)")
  else()
    set(_who "${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt")
  endif()
  while(_queue)
    list(POP_FRONT _queue name)
    if(name IN_LIST _seen)
      continue()
    endif()
    list(APPEND _seen "${name}")
    _ddes_component_kind("${name}" kind)
    set(_c_inc "")
    set(_c_libs "")
    set(_c_libdirs "")
    set(_c_targets "")
    set(_c_found TRUE)
    if(kind STREQUAL "ws")
      get_property(_configured GLOBAL PROPERTY DDES_PKG_${name}_CONFIGURED)
      if(name STREQUAL "${_DDES_CURRENT_PACKAGE}")
        message(FATAL_ERROR "${_who} asks for itself as a component ('${name}'): remove it "
                            "from find_package(catkin REQUIRED COMPONENTS ...)")
      elseif(NOT _configured)
        message(FATAL_ERROR "${_who} asks for '${name}', a package of this workspace that is "
                            "configured after it: add <depend>${name}</depend> to the "
                            "package.xml of '${_DDES_CURRENT_PACKAGE}', so catkin orders "
                            "'${name}' first")
      endif()
      get_property(_c_inc GLOBAL PROPERTY DDES_PKG_${name}_INCLUDE_DIRS)
      get_property(_c_libs GLOBAL PROPERTY DDES_PKG_${name}_LIBRARIES)
      get_property(_c_targets GLOBAL PROPERTY DDES_PKG_${name}_EXPORTED_TARGETS)
      get_property(_deps GLOBAL PROPERTY DDES_PKG_${name}_CATKIN_DEPENDS)
      list(APPEND _c_inc "${CATKIN_DEVEL_PREFIX}/include" "${DDES_GENCPP_INCLUDE_DIR}"
                         "${DDES_ROSCPP_INCLUDE_DIR}")
      list(APPEND _queue ${_deps})
    elseif(kind STREQUAL "library")
      _ddes_roscpp_library()
      if(NOT TARGET ddes_roscpp)
        message(FATAL_ERROR "${_who} asks for '${name}', which is ddes's roscpp library, but "
                            "its sources are missing (${DDES_ROSCPP_SOURCE_DIR}/CMakeLists.txt): "
                            "this ddes installation is incomplete; reinstall ddes")
      endif()
      _ddes_gencpp_bundled(${DDES_COMPONENT_${name}_MESSAGES})
      foreach(_m ${DDES_COMPONENT_${name}_MESSAGES})
        _ddes_dummy_targets(${_m})
      endforeach()
      set(_c_inc "${DDES_GENCPP_INCLUDE_DIR}" "${DDES_ROSCPP_INCLUDE_DIR}")
      set(_c_libs ddes_roscpp Threads::Threads)
      get_property(_c_libdirs GLOBAL PROPERTY DDES_ROSCPP_LIBRARY_DIR)
      if(name IN_LIST DDES_MESSAGE_PACKAGES)  # actionlib: a library and messages
        _ddes_gencpp_bundled(${name})
        _ddes_dummy_targets(${name})
        set(_c_targets ${name}_generate_messages_cpp)
      endif()
    elseif(kind STREQUAL "messages")
      _ddes_gencpp_bundled(${name})
      _ddes_dummy_targets(${name})
      set(_c_inc "${DDES_GENCPP_INCLUDE_DIR}" "${DDES_ROSCPP_INCLUDE_DIR}")
      set(_c_targets ${name}_generate_messages_cpp)
    elseif(kind STREQUAL "noop")
      # rospy, message_generation, message_runtime, ...: nothing for C++ code
    else()
      set(_c_found FALSE)
      set(_all_found FALSE)
      set(_text "find_package(catkin REQUIRED COMPONENTS ...) in ${_who}: unknown component '${name}'. It is not a package of this workspace (${CATKIN_SOURCE_SPACE}), not one of ddes's (${DDES_LIBRARY_COMPONENTS};${DDES_NOOP_COMPONENTS}), and no package of that name has messages on ddes's package path (ddes's bundled packages, DDES_PACKAGE_PATH). Fix the name, put the package into the workspace's src/ (or its folder on DDES_PACKAGE_PATH), or remove '${name}' from the components.")
      string(REPLACE ";" ", " _text "${_text}")
      if(required)
        message(FATAL_ERROR "${_text}")
      else()
        message(WARNING "${_text}")
      endif()
    endif()
    set(${name}_FOUND ${_c_found} PARENT_SCOPE)
    set(${name}_INCLUDE_DIRS "${_c_inc}" PARENT_SCOPE)
    set(${name}_LIBRARIES "${_c_libs}" PARENT_SCOPE)
    set(${name}_LIBRARY_DIRS "${_c_libdirs}" PARENT_SCOPE)
    set(${name}_EXPORTED_TARGETS "${_c_targets}" PARENT_SCOPE)
    list(APPEND _inc ${_c_inc})
    list(APPEND _libs ${_c_libs})
    list(APPEND _libdirs ${_c_libdirs})
    list(APPEND _targets ${_c_targets})
  endwhile()
  foreach(var _inc _libs _libdirs _targets)
    if(${var})
      list(REMOVE_DUPLICATES ${var})
    endif()
  endforeach()
  set(${prefix}_INCLUDE_DIRS "${_inc}" PARENT_SCOPE)
  set(${prefix}_LIBRARIES "${_libs}" PARENT_SCOPE)
  set(${prefix}_LIBRARY_DIRS "${_libdirs}" PARENT_SCOPE)
  set(${prefix}_EXPORTED_TARGETS "${_targets}" PARENT_SCOPE)
  set(${prefix}_ALL_FOUND ${_all_found} PARENT_SCOPE)
  set_property(DIRECTORY APPEND PROPERTY DDES_COMPONENTS ${_seen})
endfunction()

# The destinations of the current project (catkin_destinations()).
macro(_ddes_catkin_destinations)
  set(CATKIN_PACKAGE_BIN_DESTINATION "${CATKIN_GLOBAL_LIBEXEC_DESTINATION}/${PROJECT_NAME}")
  set(CATKIN_PACKAGE_ETC_DESTINATION "${CATKIN_GLOBAL_ETC_DESTINATION}/${PROJECT_NAME}")
  set(CATKIN_PACKAGE_INCLUDE_DESTINATION "${CATKIN_GLOBAL_INCLUDE_DESTINATION}/${PROJECT_NAME}")
  set(CATKIN_PACKAGE_LIB_DESTINATION "${CATKIN_GLOBAL_LIB_DESTINATION}")
  set(CATKIN_PACKAGE_LIBEXEC_DESTINATION "${CATKIN_GLOBAL_LIBEXEC_DESTINATION}/${PROJECT_NAME}")
  set(CATKIN_PACKAGE_PYTHON_DESTINATION "${CATKIN_GLOBAL_PYTHON_DESTINATION}/${PROJECT_NAME}")
  set(CATKIN_PACKAGE_SHARE_DESTINATION "${CATKIN_GLOBAL_SHARE_DESTINATION}/${PROJECT_NAME}")
endmacro()

# find_package(catkin ...): called by catkinConfig.cmake in the package's scope.
macro(_ddes_catkin_find)
  set(catkin_FOUND TRUE)
  set(catkin_VERSION "${DDES_CATKIN_VERSION}")
  set(catkin_DEFINITIONS "")
  if(catkin_FIND_COMPONENTS)
    _ddes_resolve(catkin "${catkin_FIND_REQUIRED}" ${catkin_FIND_COMPONENTS})
    if(NOT catkin_ALL_FOUND)
      set(catkin_FOUND FALSE)
    endif()
  elseif(NOT DEFINED catkin_INCLUDE_DIRS)
    set(catkin_INCLUDE_DIRS "${CATKIN_DEVEL_PREFIX}/include")
    set(catkin_LIBRARIES "")
    set(catkin_LIBRARY_DIRS "")
    set(catkin_EXPORTED_TARGETS "")
  endif()
  if(PROJECT_NAME AND NOT PROJECT_NAME STREQUAL "Project")
    _ddes_catkin_destinations()
  endif()
endmacro()

# find_package(X) for a single component X (the configs the Python side writes call this).
macro(_ddes_find_component name)
  _ddes_resolve(_ddes_fc "${${name}_FIND_REQUIRED}" ${name})
  set(${name}_INCLUDE_DIRS ${_ddes_fc_INCLUDE_DIRS})
  set(${name}_LIBRARIES ${_ddes_fc_LIBRARIES})
  set(${name}_LIBRARY_DIRS ${_ddes_fc_LIBRARY_DIRS})
  set(${name}_EXPORTED_TARGETS ${_ddes_fc_EXPORTED_TARGETS})
  set(${name}_DEFINITIONS "")
endmacro()

# -- catkin_package() ----------------------------------------------------------------------------
function(catkin_package)
  cmake_parse_arguments(ARG "SKIP_CMAKE_CONFIG_GENERATION;SKIP_PKG_CONFIG_GENERATION" ""
                        "INCLUDE_DIRS;LIBRARIES;CATKIN_DEPENDS;DEPENDS;CFG_EXTRAS;EXPORTED_TARGETS"
                        ${ARGN})
  if(NOT PROJECT_NAME OR PROJECT_NAME STREQUAL "Project")
    message(FATAL_ERROR "catkin_package() PROJECT_NAME is not set: call project() before "
                        "catkin_package()")
  endif()
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "catkin_package() called with unused arguments: "
                        "${ARG_UNPARSED_ARGUMENTS}")
  endif()
  if(DEFINED _DDES_CURRENT_PACKAGE AND NOT PROJECT_NAME STREQUAL _DDES_CURRENT_PACKAGE)
    message(FATAL_ERROR "catkin_package() package name '${_DDES_CURRENT_PACKAGE}' in "
                        "'${CMAKE_CURRENT_SOURCE_DIR}/package.xml' does not match the current "
                        "PROJECT_NAME '${PROJECT_NAME}': call project(${_DDES_CURRENT_PACKAGE}) "
                        "(or rename the package in package.xml)")
  endif()
  get_property(_called GLOBAL PROPERTY DDES_PKG_${PROJECT_NAME}_CATKIN_PACKAGE)
  if(_called)
    message(FATAL_ERROR "catkin_package() called a second time in '${CMAKE_CURRENT_SOURCE_DIR}': "
                        "call it once")
  endif()
  set(_inc "")
  foreach(idir ${ARG_INCLUDE_DIRS})
    if(IS_ABSOLUTE "${idir}")
      if(NOT IS_DIRECTORY "${idir}")
        message(FATAL_ERROR "catkin_package() absolute include dir '${idir}' does not exist")
      endif()
      list(APPEND _inc "${idir}")
    else()
      if(NOT IS_DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}/${idir}")
        message(FATAL_ERROR "catkin_package() include dir '${idir}' does not exist relative to "
                            "'${CMAKE_CURRENT_SOURCE_DIR}'")
      endif()
      list(APPEND _inc "${CMAKE_CURRENT_SOURCE_DIR}/${idir}")
    endif()
  endforeach()
  foreach(dep ${ARG_CATKIN_DEPENDS})
    _ddes_component_kind("${dep}" kind)
    if(kind STREQUAL "unknown")
      message(FATAL_ERROR "catkin_package() CATKIN_DEPENDS on '${dep}', which is not a catkin "
                          "package ddes knows (not in this workspace, not one of ddes's, no "
                          "messages of that name on ddes's package path): fix or remove it")
    endif()
  endforeach()
  foreach(dep ${ARG_DEPENDS})
    string(TOUPPER "${dep}" _up)
    if(NOT ${dep}_FOUND AND NOT ${_up}_FOUND)
      message(WARNING "catkin_package() DEPENDS on '${dep}', which has not been "
                      "find_package()-ed before (real catkin stops here): call "
                      "find_package(${dep}) first")
    endif()
  endforeach()
  # executables added before catkin_package() stay in the build space, as with catkin
  get_property(_targets DIRECTORY PROPERTY BUILDSYSTEM_TARGETS)
  foreach(t ${_targets})
    get_target_property(_type ${t} TYPE)
    get_target_property(_out ${t} RUNTIME_OUTPUT_DIRECTORY)
    if(_type STREQUAL "EXECUTABLE" AND NOT _out)
      message(WARNING "add_executable(${t} ...) comes before catkin_package() in "
                      "${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt: catkin builds it in "
                      "${CMAKE_CURRENT_BINARY_DIR}, not in devel/lib/${PROJECT_NAME} where "
                      "rosrun looks. Move catkin_package() above add_executable().")
    endif()
  endforeach()
  get_property(_msg_targets GLOBAL PROPERTY DDES_PKG_${PROJECT_NAME}_MESSAGE_TARGETS)
  set_property(GLOBAL PROPERTY DDES_PKG_${PROJECT_NAME}_CATKIN_PACKAGE TRUE)
  set_property(GLOBAL PROPERTY DDES_PKG_${PROJECT_NAME}_INCLUDE_DIRS ${_inc})
  set_property(GLOBAL PROPERTY DDES_PKG_${PROJECT_NAME}_LIBRARIES ${ARG_LIBRARIES})
  set_property(GLOBAL PROPERTY DDES_PKG_${PROJECT_NAME}_CATKIN_DEPENDS ${ARG_CATKIN_DEPENDS})
  set_property(GLOBAL PROPERTY DDES_PKG_${PROJECT_NAME}_EXPORTED_TARGETS
               ${_msg_targets} ${ARG_EXPORTED_TARGETS})

  set(CATKIN_PACKAGE_BIN_DESTINATION "${CATKIN_GLOBAL_LIBEXEC_DESTINATION}/${PROJECT_NAME}" PARENT_SCOPE)
  set(CATKIN_PACKAGE_ETC_DESTINATION "${CATKIN_GLOBAL_ETC_DESTINATION}/${PROJECT_NAME}" PARENT_SCOPE)
  set(CATKIN_PACKAGE_INCLUDE_DESTINATION "${CATKIN_GLOBAL_INCLUDE_DESTINATION}/${PROJECT_NAME}" PARENT_SCOPE)
  set(CATKIN_PACKAGE_LIB_DESTINATION "${CATKIN_GLOBAL_LIB_DESTINATION}" PARENT_SCOPE)
  set(CATKIN_PACKAGE_LIBEXEC_DESTINATION "${CATKIN_GLOBAL_LIBEXEC_DESTINATION}/${PROJECT_NAME}" PARENT_SCOPE)
  set(CATKIN_PACKAGE_PYTHON_DESTINATION "${CATKIN_GLOBAL_PYTHON_DESTINATION}/${PROJECT_NAME}" PARENT_SCOPE)
  set(CATKIN_PACKAGE_SHARE_DESTINATION "${CATKIN_GLOBAL_SHARE_DESTINATION}/${PROJECT_NAME}" PARENT_SCOPE)
  # catkin's devel space layout: executables in devel/lib/<pkg>, libraries in devel/lib
  file(MAKE_DIRECTORY "${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}")
  set(CMAKE_RUNTIME_OUTPUT_DIRECTORY "${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}" PARENT_SCOPE)
  set(CMAKE_LIBRARY_OUTPUT_DIRECTORY "${CATKIN_DEVEL_PREFIX}/lib" PARENT_SCOPE)
  set(CMAKE_ARCHIVE_OUTPUT_DIRECTORY "${CATKIN_DEVEL_PREFIX}/lib" PARENT_SCOPE)
  set(${PROJECT_NAME}_INCLUDE_DIRS ${_inc} PARENT_SCOPE)
  set(${PROJECT_NAME}_LIBRARIES ${ARG_LIBRARIES} PARENT_SCOPE)
endfunction()

# -- messages ------------------------------------------------------------------------------------
function(_ddes_check_generator what needs)
  get_property(_components DIRECTORY PROPERTY DDES_COMPONENTS)
  set(_ok FALSE)
  foreach(n ${needs})
    if(n IN_LIST _components)
      set(_ok TRUE)
    endif()
  endforeach()
  if(NOT _ok)
    list(GET needs 0 _first)
    message(WARNING "${what} in ${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt without '${_first}' "
                    "in find_package(catkin REQUIRED COMPONENTS ...): real catkin stops with "
                    "\"Unknown CMake command\" there; add ${_first} to the components")
  endif()
endfunction()

# add_message_files / add_service_files / add_action_files: remember the files of the package.
function(_ddes_add_interface_files kind ext what)
  cmake_parse_arguments(ARG "NOINSTALL" "DIRECTORY;BASE_DIR" "FILES" ${ARGN})
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "${what}() called with unused arguments: ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT ARG_DIRECTORY)
    set(ARG_DIRECTORY "${kind}")
  endif()
  if(ARG_BASE_DIR)
    set(_dir "${ARG_BASE_DIR}")
  elseif(IS_ABSOLUTE "${ARG_DIRECTORY}")
    set(_dir "${ARG_DIRECTORY}")
  else()
    set(_dir "${CMAKE_CURRENT_SOURCE_DIR}/${ARG_DIRECTORY}")
  endif()
  get_filename_component(_dir "${_dir}" ABSOLUTE)
  if(NOT IS_DIRECTORY "${_dir}")
    message(FATAL_ERROR "${what}() directory not found: ${_dir}")
  endif()
  if(NOT _dir STREQUAL "${CMAKE_CURRENT_SOURCE_DIR}/${kind}")
    message(FATAL_ERROR "${what}(DIRECTORY ${ARG_DIRECTORY}): ddes reads a package's ${ext} "
                        "files from its ${kind}/ folder only; move them to "
                        "${CMAKE_CURRENT_SOURCE_DIR}/${kind}")
  endif()
  if(NOT ARG_FILES)
    file(GLOB ARG_FILES RELATIVE "${_dir}" "${_dir}/*${ext}")
    list(SORT ARG_FILES)
  endif()
  foreach(f ${ARG_FILES})
    get_filename_component(_name "${f}" NAME)
    if(NOT EXISTS "${_dir}/${f}")
      message(FATAL_ERROR "${what}() file not found: ${_dir}/${f}")
    endif()
    if(NOT _name MATCHES "\\${ext}$" OR NOT _name STREQUAL "${f}")
      message(FATAL_ERROR "${what}() expects ${ext} files directly in ${_dir}, not '${f}'")
    endif()
    set_property(DIRECTORY APPEND PROPERTY DDES_INTERFACE_FILES "${_dir}/${f}")
  endforeach()
endfunction()

function(add_message_files)
  _ddes_check_generator(add_message_files "message_generation;genmsg")
  _ddes_add_interface_files(msg .msg add_message_files ${ARGN})
endfunction()

function(add_service_files)
  _ddes_check_generator(add_service_files "message_generation;genmsg")
  _ddes_add_interface_files(srv .srv add_service_files ${ARGN})
endfunction()

function(add_action_files)
  _ddes_check_generator(add_action_files "actionlib_msgs")
  _ddes_add_interface_files(action .action add_action_files ${ARGN})
endfunction()

function(generate_messages)
  cmake_parse_arguments(ARG "" "" "DEPENDENCIES;LANGS" ${ARGN})
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "generate_messages() called with unused arguments: "
                        "${ARG_UNPARSED_ARGUMENTS}")
  endif()
  _ddes_check_generator(generate_messages "message_generation;genmsg")
  set(pkg "${PROJECT_NAME}")
  get_property(_called GLOBAL PROPERTY DDES_PKG_${pkg}_CATKIN_PACKAGE)
  if(_called)
    message(FATAL_ERROR "generate_messages() must be called before catkin_package() in "
                        "project '${pkg}'")
  endif()
  foreach(dep ${ARG_DEPENDENCIES})
    _ddes_component_kind("${dep}" kind)
    if(NOT kind STREQUAL "messages" AND NOT kind STREQUAL "ws" AND NOT kind STREQUAL "library")
      message(FATAL_ERROR "generate_messages(DEPENDENCIES ${dep}): '${dep}' is not a package "
                          "with messages ddes knows (this workspace, ddes's bundled packages, "
                          "DDES_PACKAGE_PATH)")
    endif()
    if(kind STREQUAL "messages" OR kind STREQUAL "library")
      _ddes_gencpp_bundled(${dep})
      _ddes_dummy_targets(${dep})
    endif()
  endforeach()
  get_property(_files DIRECTORY PROPERTY DDES_INTERFACE_FILES)
  set(_types "")
  set(_headers "")
  set(_out "${CATKIN_DEVEL_PREFIX}/include/${pkg}")
  set(_nmsg 0)
  set(_nsrv 0)
  set(_nact 0)
  foreach(f ${_files})
    get_filename_component(_name "${f}" NAME_WE)
    get_filename_component(_ext "${f}" LAST_EXT)
    list(APPEND _types "${pkg}/${_name}")
    if(_ext STREQUAL ".msg")
      math(EXPR _nmsg "${_nmsg} + 1")
      list(APPEND _headers "${_out}/${_name}.h")
    elseif(_ext STREQUAL ".srv")
      math(EXPR _nsrv "${_nsrv} + 1")
      list(APPEND _headers "${_out}/${_name}.h" "${_out}/${_name}Request.h"
                           "${_out}/${_name}Response.h")
    else()
      math(EXPR _nact "${_nact} + 1")
      foreach(s Action ActionGoal ActionResult ActionFeedback Goal Result Feedback)
        list(APPEND _headers "${_out}/${_name}${s}.h")
      endforeach()
    endif()
  endforeach()
  message(STATUS "${pkg}: ${_nmsg} messages, ${_nsrv} services, ${_nact} actions (ddes gencpp)")
  set(_stamp "${CMAKE_CURRENT_BINARY_DIR}/ddes_gencpp/${pkg}.stamp")
  set(_cmd "${DDES_PYTHON}" -m ddes.roscpp.catkin genmsg --package "${pkg}"
           --source "${CATKIN_SOURCE_SPACE}" --devel-include "${CATKIN_DEVEL_PREFIX}/include"
           --gencpp-include "${DDES_GENCPP_INCLUDE_DIR}" --stamp "${_stamp}"
           --dependencies ${ARG_DEPENDENCIES} --types ${_types})
  set(_targets "")
  if(_types)
    # at configure time (so a node that forgets add_dependencies still finds its headers),
    # and again at build time whenever a definition changes
    execute_process(COMMAND ${_cmd} RESULT_VARIABLE _rc ERROR_VARIABLE _err
                    ERROR_STRIP_TRAILING_WHITESPACE)
    if(NOT _rc EQUAL 0)
      message(FATAL_ERROR "generate_messages() in project '${pkg}' failed:\n${_err}")
    endif()
    add_custom_command(
      OUTPUT "${_stamp}"
      COMMAND ${_cmd}
      DEPENDS ${_files} ${DDES_GENERATOR_SOURCES}
      BYPRODUCTS ${_headers}
      COMMENT "Generating C++ code from ${pkg} messages, services and actions (ddes gencpp)"
      VERBATIM)
    add_custom_target(${pkg}_generate_messages_cpp DEPENDS "${_stamp}")
  else()
    add_custom_target(${pkg}_generate_messages_cpp)
  endif()
  foreach(dep ${ARG_DEPENDENCIES})
    if(TARGET ${dep}_generate_messages_cpp)
      add_dependencies(${pkg}_generate_messages_cpp ${dep}_generate_messages_cpp)
    endif()
  endforeach()
  add_custom_target(${pkg}_gencpp)
  add_dependencies(${pkg}_gencpp ${pkg}_generate_messages_cpp)
  add_custom_target(${pkg}_generate_messages ALL)
  add_dependencies(${pkg}_generate_messages ${pkg}_generate_messages_cpp)
  foreach(lang py eus lisp nodejs)
    add_custom_target(${pkg}_generate_messages_${lang})
  endforeach()
  foreach(gen genpy geneus genlisp gennodejs)
    add_custom_target(${pkg}_${gen})
  endforeach()
  set(_exported ${pkg}_generate_messages_cpp ${pkg}_generate_messages_eus
                ${pkg}_generate_messages_lisp ${pkg}_generate_messages_nodejs
                ${pkg}_generate_messages_py)
  set_property(GLOBAL PROPERTY DDES_PKG_${pkg}_MESSAGE_TARGETS ${_exported})
  set(${pkg}_EXPORTED_TARGETS ${${pkg}_EXPORTED_TARGETS} ${_exported} PARENT_SCOPE)
endfunction()

# -- accepted for compatibility ------------------------------------------------------------------
function(catkin_install_python)
  cmake_parse_arguments(ARG "OPTIONAL" "DESTINATION" "PROGRAMS" ${ARGN})
  if(NOT ARG_PROGRAMS)
    message(FATAL_ERROR "catkin_install_python() called without required PROGRAMS argument.")
  endif()
  if(NOT ARG_DESTINATION)
    message(FATAL_ERROR "catkin_install_python() called without required DESTINATION argument.")
  endif()
  foreach(f ${ARG_PROGRAMS})
    if(NOT IS_ABSOLUTE "${f}")
      set(f "${CMAKE_CURRENT_SOURCE_DIR}/${f}")
    endif()
    if(NOT EXISTS "${f}" AND NOT ARG_OPTIONAL)
      message(FATAL_ERROR "catkin_install_python() called with non-existing file '${f}'.")
    endif()
    if(EXISTS "${f}")
      install(PROGRAMS "${f}" DESTINATION "${ARG_DESTINATION}")
    endif()
  endforeach()
endfunction()

function(catkin_python_setup)
endfunction()

function(catkin_metapackage)
endfunction()

function(roslaunch_add_file_check)
endfunction()

function(add_rostest file)
  message(STATUS "ddes: add_rostest(${file}) noted: ddes runs rostests itself, on simulated "
                 "time: ddes rostest ${PROJECT_NAME} ${file}")
endfunction()

function(catkin_add_nosetests)
  message(STATUS "ddes: catkin_add_nosetests(${ARGV0}) noted: run Python tests with pytest")
endfunction()

# gtest targets are built only by `make tests`, and only where GTest is installed.
function(catkin_add_gtest target)
  cmake_parse_arguments(ARG "" "TIMEOUT;WORKING_DIRECTORY" "" ${ARGN})
  find_package(GTest QUIET)
  if(NOT GTest_FOUND AND NOT GTEST_FOUND)
    message(STATUS "ddes: catkin_add_gtest(${target}) skipped: GTest is not installed "
                   "(apt install libgtest-dev)")
    return()
  endif()
  add_executable(${target} EXCLUDE_FROM_ALL ${ARG_UNPARSED_ARGUMENTS})
  target_link_libraries(${target} GTest::GTest GTest::Main)
  add_dependencies(tests ${target})
endfunction()

function(add_rostest_gtest target launch_file)
  message(STATUS "ddes: add_rostest_gtest(${target} ${launch_file}) noted: ddes runs rostests "
                 "itself (ddes rostest ${PROJECT_NAME} ${launch_file})")
  catkin_add_gtest(${target} ${ARGN})
endfunction()

function(generate_dynamic_reconfigure_options)
  message(FATAL_ERROR "generate_dynamic_reconfigure_options(${ARGN}) in ${PROJECT_NAME}: "
                      "ddes's roscpp has no C++ dynamic_reconfigure server; write that node in "
                      "Python (ddes.dynamic_reconfigure, or rospy with dynamic_reconfigure)")
endfunction()
