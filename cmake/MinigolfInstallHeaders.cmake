# Run at install time (install(CODE) in cmake/MinigolfPackage.cmake): copies the entry headers of
# include/minigolf/ to <prefix>/include/minigolf/ and the headers they include, directly or
# through each other, to <prefix>/include/minigolf/<part>/, with every project include
# "<part>/x.hpp" written as "minigolf/<part>/x.hpp". In the source tree the headers include each
# other relative to src/ (that is not changed for an install); installed, one include directory
# (<prefix>/include) serves them and no header name of ours ("core/io.hpp") can shadow or be
# shadowed by a user's.
#
# The entry headers are the API: a header no entry header reaches is internal to its library
# (the YAML reader, wire formats, file layouts, a harness's parts) and is not installed, so an
# outside program cannot come to depend on it.
#
# Expects: MINIGOLF_SOURCE_DIR, MINIGOLF_STAGING_DIR (a scratch folder in the build tree) and
# MINIGOLF_SUBSYSTEMS (a list). Each install prefix stages in its own subfolder, so two installs
# from one build tree running at once (the install tests) never remove each other's files.
string(MD5 _mg_prefix_key "${CMAKE_INSTALL_PREFIX}")
set(MINIGOLF_STAGING_DIR "${MINIGOLF_STAGING_DIR}/${_mg_prefix_key}")
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

# The project headers `file` includes ("<part>/x.hpp", relative to src/), appended to `out`.
function(_mg_project_includes file out)
  file(STRINGS "${file}" lines REGEX "^#include \"(${_mg_alternatives})/")
  set(found ${${out}})
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" included "${line}")
    list(APPEND found "${included}")
  endforeach()
  set(${out} ${found} PARENT_SCOPE)
endfunction()

file(GLOB entries "${MINIGOLF_SOURCE_DIR}/include/minigolf/*.hpp")
set(queue)
foreach(h IN LISTS entries)
  _mg_install_rewritten("${h}" "")
  _mg_project_includes("${h}" queue)
endforeach()
set(installed)
while(queue)
  list(POP_FRONT queue rel)
  list(FIND installed "${rel}" seen)  # (not IN_LIST: an install script runs with old policies)
  if(NOT seen EQUAL -1)
    continue()
  endif()
  list(APPEND installed "${rel}")
  set(header "${MINIGOLF_SOURCE_DIR}/src/${rel}")
  if(NOT EXISTS "${header}")
    message(FATAL_ERROR "an installed header includes ${rel}, which src/ does not have")
  endif()
  get_filename_component(subdir "${rel}" DIRECTORY)
  _mg_install_rewritten("${header}" "${subdir}")
  _mg_project_includes("${header}" queue)
endwhile()
