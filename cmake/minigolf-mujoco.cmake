# MuJoCo as the imported target mujoco::mujoco: for the build (CMakeLists.txt) and for projects
# using the installed package (minigolfConfig.cmake includes this file). Debian 12's own
# mujocoConfig.cmake lists qhull include paths its package does not install (CMake then refuses
# the target), so the library and its headers are found directly. A mujoco::mujoco defined
# before (a project's own) is used as it is.
if(NOT TARGET mujoco::mujoco)
  find_library(MINIGOLF_MUJOCO_LIBRARY mujoco)
  find_path(MINIGOLF_MUJOCO_INCLUDE_DIR mujoco/mujoco.h)
  if(MINIGOLF_MUJOCO_LIBRARY AND MINIGOLF_MUJOCO_INCLUDE_DIR)
    add_library(mujoco::mujoco UNKNOWN IMPORTED)
    set_target_properties(mujoco::mujoco PROPERTIES
      IMPORTED_LOCATION "${MINIGOLF_MUJOCO_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${MINIGOLF_MUJOCO_INCLUDE_DIR}")
  endif()
endif()
