#pragma once
/// How MuJoCo's fatal errors end a program.
///
/// MuJoCo 2.2.2 reports a fatal error (mju_error: a model it cannot use, an exhausted mjData
/// stack, an OpenGL context too old for the renderer) through the process-wide `mju_user_error`;
/// unset, it prints "ERROR: ...", waits for Enter on standard input and exits. A handler cannot
/// return into MuJoCo (the caller's state is undefined) nor throw through its C frames, so the
/// only choice is how to exit. The library never sets the handler: the process belongs to the
/// program. The `minigolf` command sets it once at start; the Python module when it is imported
/// (an interpreter must never wait for Enter); a program using the C++ API decides for itself.
/// The library checks what it passes to MuJoCo (e.g. an mjData of the world it steps), so these
/// handlers are a last line, not the policy.
namespace mg::sim {

/// Sets MuJoCo's process-wide error handler to one that prints
/// "minigolf: error: MuJoCo: <message>" on standard error and ends the process with status 1
/// (std::_Exit: no atexit handlers, whose state the error may have left broken). Call it before
/// starting threads; idempotent.
void exit_on_mujoco_error();

/// Sets MuJoCo's process-wide warning handler to one that prints
/// "minigolf: warning: MuJoCo: <message>" on standard error (unset, MuJoCo prints to standard
/// output, where it would break a JSON answer, and appends to MUJOCO_LOG.TXT in the working
/// folder). Call it before starting threads; idempotent.
void print_mujoco_warnings();

}  // namespace mg::sim
