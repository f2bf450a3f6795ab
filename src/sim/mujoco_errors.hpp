#pragma once
/// How MuJoCo's fatal errors end a program.
///
/// MuJoCo 2.2.2 reports a fatal error (mju_error: a model it cannot use, an exhausted mjData
/// stack, an OpenGL context too old for the renderer) through the process-wide `mju_user_error`;
/// unset, it prints "ERROR: ...", waits for Enter on standard input and exits. A handler cannot
/// return into MuJoCo (the caller's state is undefined) nor throw through its C frames, so the
/// only choice is how to exit. The library never sets the handler: the process belongs to the
/// program. The `minigolf` command sets it once at start; the Python module when it makes a
/// Renderer (as before); a program using the C++ API decides for itself.
namespace mg::sim {

/// Sets MuJoCo's process-wide error handler to one that prints
/// "minigolf: error: MuJoCo: <message>" on standard error and ends the process with status 1
/// (std::_Exit: no atexit handlers, whose state the error may have left broken). Call it before
/// starting threads; idempotent.
void exit_on_mujoco_error();

}  // namespace mg::sim
