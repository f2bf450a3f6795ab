// The `minigolf` Python module (pybind11): the library's fields, worlds, putts, learners, DS
// rollouts, teacher and experiments, bound part by part (field_, world_, putt_, system_,
// learner_, render_ and game_bindings.cpp). Units: metres, seconds, radians, m/s. Long calls
// release the GIL; mg::InputError -> ValueError, mg::IoError -> OSError, mg::NumericalError ->
// minigolf.NumericalError (a RuntimeError), other mg::Error -> RuntimeError, with the messages
// the CLI prints after "minigolf: error: ".
#include <pybind11/pybind11.h>

#include <exception>

#include "core/error.hpp"
#include "python/bindings.hpp"
#include "sim/mujoco_errors.hpp"
#include "system/distributed.hpp"

namespace py = pybind11;
using namespace mg;

PYBIND11_MODULE(_minigolf, m) {
  // MuJoCo's fatal errors end the process with one line on stderr, never with MuJoCo's default
  // wait for Enter on standard input (a handler cannot raise through MuJoCo's C frames; the
  // bindings check what they pass to MuJoCo so that none is reached). Its warnings go to stderr
  // instead of MUJOCO_LOG.TXT in the working folder and standard output.
  sim::exit_on_mujoco_error();
  sim::print_mujoco_warnings();
  m.doc() =
      "A simulated Barrett WAM that learns to putt: fields, worlds, putts, learners, DS rollouts, "
      "teacher, evaluation. Units: m, s, rad, m/s.";

  static py::exception<NumericalError> numerical(m, "NumericalError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const IoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const NumericalError& e) {
      numerical(e.what());
    } catch (const Error& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
  m.attr("mpi_built") = system::mpi_built();

  python::bind_fields(m);
  python::bind_worlds(m);
  python::bind_putts(m);
  python::bind_system(m);
  python::bind_learners(m);
  python::bind_render(m);
  python::bind_game(m);
  python::bind_round(m);
}
