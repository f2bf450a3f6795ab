# The installed C++ package (docs/cpp-api.md): `cmake --install build --prefix P` puts the
# libraries in P/lib, the headers in P/include/minigolf, minigolfConfig.cmake (+ version and
# targets files, namespace minigolf::) in P/lib/cmake/minigolf and the shipped data in
# P/share/minigolf/data, so that another project can `find_package(minigolf)` and link
# minigolf::minigolf. Included by the top-level CMakeLists.txt after every library is defined.
include(CMakePackageConfigHelpers)

# Every library of the public API, in the order of their layers (ARCHITECTURE.md).
set(MINIGOLF_SUBSYSTEMS core field plant sim belief robot stats learning ds perception control system
    teacher selfteach experiments game viz)

# minigolf::minigolf: all of them, and the entry headers of include/minigolf/.
add_library(mg_minigolf INTERFACE)
add_library(minigolf::minigolf ALIAS mg_minigolf)
target_include_directories(mg_minigolf INTERFACE
  $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>)
set_target_properties(mg_minigolf PROPERTIES EXPORT_NAME minigolf)
set(_mg_targets mg_minigolf)
foreach(sub IN LISTS MINIGOLF_SUBSYSTEMS)
  set_target_properties(mg_${sub} PROPERTIES EXPORT_NAME ${sub})
  target_link_libraries(mg_minigolf INTERFACE mg_${sub})
  list(APPEND _mg_targets mg_${sub})
endforeach()

set(MINIGOLF_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/minigolf)
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
