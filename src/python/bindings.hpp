#pragma once
/// What the binding files of the `minigolf` module share: numpy conversions, the Python `Data` (an
/// mjData of a world), the per-thread `SystemData`, and the functions that bind each part.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <mujoco/mujoco.h>
#include <Eigen/Dense>

#include "core/error.hpp"
#include "sim/world.hpp"
#include "system/putt.hpp"
#include "system/system.hpp"

namespace mg::python {

namespace py = pybind11;

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A numpy array over `p` (no copy) that keeps `owner` alive; read-only unless `writeable`.
template <typename T>
inline py::array view(T* p, py::ssize_t rows, py::ssize_t cols, py::handle owner, bool writeable) {
  std::vector<py::ssize_t> shape{rows};
  if (cols > 1) shape.push_back(cols);
  py::array a(py::dtype::of<T>(), shape, p, owner);
  if (!writeable) a.attr("setflags")(py::arg("write") = false);
  return a;
}

inline py::array_t<double> matrix(const Eigen::MatrixXd& m) {
  py::array_t<double> a({m.rows(), m.cols()});
  auto r = a.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) r(i, j) = m(i, j);
  return a;
}

inline Eigen::MatrixXd to_matrix(const Array& a, const char* what) {
  if (a.ndim() != 2)
    throw InputError(
        fmt::format("{}: expected a 2-D array (N x D), got {} dimensions", what, a.ndim()));
  Eigen::MatrixXd m(a.shape(0), a.shape(1));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (py::ssize_t j = 0; j < a.shape(1); ++j) m(i, j) = r(i, j);
  return m;
}

inline py::array_t<double> points(const std::vector<std::array<double, 2>>& p) {
  py::array_t<double> a({static_cast<py::ssize_t>(p.size()), py::ssize_t{2}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < p.size(); ++i) r(i, 0) = p[i][0], r(i, 1) = p[i][1];
  return a;
}

// ---- worlds and their MuJoCo data

/// An mjData of a world: owned (World.make_data) or borrowed from a SystemData.
struct Data {
  const sim::World* world = nullptr;
  sim::DataPtr owned;
  mjData* d = nullptr;
};

/// Throws unless `d` is an mjData of `w` (another world's would be read out of bounds).
inline mjData* data_of(const sim::World& w, const Data& d) {
  if (d.world != &w)
    throw InputError("World: this Data belongs to another world (use that world's make_data)");
  return d.d;
}

/// A SystemData that refuses to be used by two threads at once.
struct PySystemData {
  explicit PySystemData(const system::System& s) : system(&s), data(s) {}
  const system::System* system;
  system::SystemData data;
  std::mutex busy;
};

/// Throws unless `d` (none: a fresh one is made) is a SystemData of `s`: another System's
/// mjData's have other sizes, and MuJoCo would copy between them out of bounds.
inline void check_owner(const system::System& s, const PySystemData* d) {
  if (d != nullptr && d->system != &s)
    throw InputError(
        "data: this SystemData belongs to another System (use this System's make_data)");
}

class Lease {
 public:
  explicit Lease(PySystemData* d) : d_(d) {
    if (d_ && !d_->busy.try_lock())
      throw std::runtime_error("SystemData: in use by another thread (make one per thread)");
  }
  ~Lease() {
    if (d_) d_->busy.unlock();
  }
  Lease(const Lease&) = delete;
  Lease& operator=(const Lease&) = delete;

 private:
  PySystemData* d_;
};

/// A putt's request, report and `minigolf putt --json` object (system::putt).
struct PuttResult {
  system::PuttSpec spec;
  system::PuttReport report;
  nlohmann::json json;
};
/// system::putt with `data` (a fresh SystemData when null; one thread at a time), the GIL released
/// (putt_bindings.cpp).
PuttResult putt(const system::System& system, PySystemData* data, const system::PuttSpec& spec);

void bind_fields(py::module_& m);  ///< Situations, Field (field_bindings.cpp)
void bind_worlds(py::module_& m);  ///< World, Data (world_bindings.cpp)
void bind_putts(py::module_& m);   ///< PuttResult (putt_bindings.cpp)
void bind_system(
    py::module_& m);  ///< SystemData, Example, Evaluation, System (system_bindings.cpp)
void bind_learners(
    py::module_& m);  ///< Model, train, load_dataset, HittingModel (learner_bindings.cpp)
void bind_render(py::module_& m);  ///< Renderer (render_bindings.cpp)
void bind_game(py::module_& m);    ///< play, courses (game_bindings.cpp)
/// load_course, LaneRegion, end_of_stroke, plan_stroke, LaunchSkill, fast_putt (round_bindings.cpp)
void bind_round(py::module_& m);

}  // namespace mg::python
