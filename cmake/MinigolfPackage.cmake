# The installed C++ package (docs/cpp-api.md): `cmake --install build --prefix P` puts the
# libraries in P/lib, the headers in P/include/minigolf, minigolfConfig.cmake (+ version and
# targets files, namespace minigolf::) in P/lib/cmake/minigolf and the shipped data in
# P/share/minigolf/data, so that another project can `find_package(minigolf)` and link
# minigolf::minigolf. Included by the top-level CMakeLists.txt after every library is defined.
include(CMakePackageConfigHelpers)

# Every library of the public API, in the order of their layers (docs/architecture.md).
set(MINIGOLF_SUBSYSTEMS core field plant sim belief robot stats learning ds perception control
    sim_backend system teacher selfteach experiments game viz)
# The controller and what it links: no MuJoCo, GLFW or simulator among them. They are their own
# export set, so that a program that drives another arm can find_package(minigolf COMPONENTS
# controller) without MuJoCo installed. The module's library (src/control) is exported under the
# name of that closure, minigolf::controller.
set(MINIGOLF_CONTROLLER_PARTS core field robot stats ds perception control)

# minigolf::minigolf: all of them, and the entry headers of include/minigolf/.
add_library(mg_minigolf INTERFACE)
add_library(minigolf::minigolf ALIAS mg_minigolf)
target_include_directories(mg_minigolf INTERFACE
  $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>)
set_target_properties(mg_minigolf PROPERTIES EXPORT_NAME minigolf)
set(_mg_targets mg_minigolf)
set(_mg_controller_targets)
foreach(sub IN LISTS MINIGOLF_SUBSYSTEMS)
  if(sub STREQUAL "control")
    set_target_properties(mg_${sub} PROPERTIES EXPORT_NAME controller)
  else()
    set_target_properties(mg_${sub} PROPERTIES EXPORT_NAME ${sub})
  endif()
  target_link_libraries(mg_minigolf INTERFACE mg_${sub})
  if(sub IN_LIST MINIGOLF_CONTROLLER_PARTS)
    list(APPEND _mg_controller_targets mg_${sub})
  else()
    list(APPEND _mg_targets mg_${sub})
  endif()
endforeach()

set(MINIGOLF_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/minigolf)
install(TARGETS ${_mg_controller_targets} EXPORT minigolfControllerTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT minigolfControllerTargets NAMESPACE minigolf:: DESTINATION ${MINIGOLF_CMAKE_DIR})
install(TARGETS ${_mg_targets} EXPORT minigolfTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT minigolfTargets NAMESPACE minigolf:: DESTINATION ${MINIGOLF_CMAKE_DIR})

# The configuration finds what the libraries link (static libraries: their private
# dependencies too); MPI only if the system library was built with it.
get_target_property(_mg_system_links mg_system LINK_LIBRARIES)
if("MPI::MPI_CXX" IN_LIST _mg_system_links)
  set(MINIGOLF_WITH_MPI TRUE)
else()
  set(MINIGOLF_WITH_MPI FALSE)
endif()
set(MINIGOLF_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/minigolf/data)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/minigolfConfig.cmake.in
  ${PROJECT_BINARY_DIR}/minigolfConfig.cmake
  INSTALL_DESTINATION ${MINIGOLF_CMAKE_DIR}
  PATH_VARS MINIGOLF_INSTALL_DATADIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/minigolfConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)  # 0.x: a minor version may change the API
install(FILES ${PROJECT_BINARY_DIR}/minigolfConfig.cmake
              ${PROJECT_BINARY_DIR}/minigolfConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/minigolf-mujoco.cmake
        DESTINATION ${MINIGOLF_CMAKE_DIR})

# Headers: copied at install time with their includes rooted at minigolf/ (see the script).
install(CODE "
  set(MINIGOLF_SOURCE_DIR \"${PROJECT_SOURCE_DIR}\")
  set(MINIGOLF_STAGING_DIR \"${PROJECT_BINARY_DIR}/install-headers\")
  set(MINIGOLF_SUBSYSTEMS \"${MINIGOLF_SUBSYSTEMS}\")
  include(\"${PROJECT_SOURCE_DIR}/cmake/MinigolfInstallHeaders.cmake\")
")
