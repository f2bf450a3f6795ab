# Run at install time (install(CODE) in CMakeLists.txt): copies the headers of the public
# subsystems to <prefix>/include/minigolf/<subsystem>/ and the entry headers of include/minigolf/
# to <prefix>/include/minigolf/, with every project include "<subsystem>/x.hpp" written as
# "minigolf/<subsystem>/x.hpp". In the source tree the headers include each other relative to
# src/ (that is not changed for an install); installed, one include directory (<prefix>/include)
# serves them and no header name of ours ("core/io.hpp") can shadow or be shadowed by a user's.
#
# Expects: MINIGOLF_SOURCE_DIR, MINIGOLF_STAGING_DIR (a scratch folder in the build tree) and
# MINIGOLF_SUBSYSTEMS (a list).
list(JOIN MINIGOLF_SUBSYSTEMS "|" _mg_alternatives)
set(_mg_pattern "#include \"(${_mg_alternatives})/")
file(REMOVE_RECURSE "${MINIGOLF_STAGING_DIR}")

function(_mg_install_rewritten header subdir)
  file(READ "${header}" text)
  string(REGEX REPLACE "${_mg_pattern}" "#include \"minigolf/\\1/" text "${text}")
  get_filename_component(name "${header}" NAME)
  set(dest "${CMAKE_INSTALL_PREFIX}/include/minigolf")
  if(subdir)
    string(APPEND dest "/${subdir}")
  endif()
  file(WRITE "${MINIGOLF_STAGING_DIR}/${subdir}/${name}" "${text}")
  file(INSTALL DESTINATION "${dest}" TYPE FILE FILES "${MINIGOLF_STAGING_DIR}/${subdir}/${name}")
endfunction()

foreach(sub IN LISTS MINIGOLF_SUBSYSTEMS)
  file(GLOB headers "${MINIGOLF_SOURCE_DIR}/src/${sub}/*.hpp")
  foreach(h IN LISTS headers)
    _mg_install_rewritten("${h}" "${sub}")
  endforeach()
endforeach()
file(GLOB entries "${MINIGOLF_SOURCE_DIR}/include/minigolf/*.hpp")
foreach(h IN LISTS entries)
  _mg_install_rewritten("${h}" "")
endforeach()
