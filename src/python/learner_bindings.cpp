// minigolf.Model, train, load_dataset (the hitting-parameter learners) and minigolf.HittingModel
// (the hitting DS: SEDS + strength GMM, RK4 rollouts).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include <fmt/format.h>

#include "ds/hitting_ds.hpp"
#include "ds/hitting_model.hpp"
#include "learning/learner.hpp"
#include "python/bindings.hpp"
#include "system/system.hpp"

namespace mg::python {
namespace {

const learning::TrainOptions kTrainDefaults{};  // the library's defaults, in one place

}  // namespace
namespace {

std::vector<std::string> default_names(int n, const std::vector<std::string>& preferred,
                                       const char* prefix) {
  if (n == static_cast<int>(preferred.size())) return preferred;
  if (n == 1 && !preferred.empty()) return {preferred[0]};
  std::vector<std::string> names;
  for (int i = 0; i < n; ++i) names.push_back(fmt::format("{}{}", prefix, i));
  return names;
}

}  // namespace

void bind_learners(py::module_& m) {
  py::class_<learning::Model>(m, "Model",
                              "A trained hitting-parameter learner (GPR, GMR or joint GMR).")
      .def_static(
          "load", [](const std::string& path) { return learning::load_model(path); },
          py::arg("path"))
      .def(
          "save",
          [](const learning::Model& mm, const std::string& path) {
            learning::save_model(mm, path);
          },
          py::arg("path"), "Writes the model file (JSON, atomically)")
      .def_property_readonly(
          "method",
          [](const learning::Model& mm) { return std::string(learning::method_name(mm.method)); })
      .def_readonly("input_names", &learning::Model::input_names)
      .def_readonly("output_names", &learning::Model::output_names)
      .def_readonly("fixed", &learning::Model::fixed,
                    "Constant quantities not learned: (name, value) pairs")
      .def(
          "predict",
          [](const learning::Model& mm, const Array& x) {
            const Eigen::MatrixXd q = to_matrix(x, "predict");
            if (q.cols() != mm.num_inputs())
              throw InputError(fmt::format("predict: expected {} input columns ({}), got {}",
                                           mm.num_inputs(), fmt::join(mm.input_names, ","),
                                           q.cols()));
            learning::Predictions p;
            {
              py::gil_scoped_release release;
              p = learning::predict(mm, q);
            }
            return py::make_tuple(matrix(p.mean), matrix(p.std));
          },
          py::arg("x"),
          "Predictive (mean, std), each (N, O), for inputs (N, I) in the model's units");

  m.def(
      "train",
      [](const Array& x, const Array& y, const std::string& method,
         std::vector<std::string> input_names, std::vector<std::string> output_names,
         int num_gaussians, const std::string& selection, int max_gaussians, int restarts,
         std::uint64_t seed, double reg_covar, std::vector<std::pair<std::string, double>> fixed) {
        learning::Dataset d;
        d.source = "train";
        d.inputs = to_matrix(x, "train: x");
        d.outputs = to_matrix(y, "train: y");
        if (d.inputs.rows() != d.outputs.rows())
          throw InputError(
              fmt::format("train: x has {} rows, y has {}", d.inputs.rows(), d.outputs.rows()));
        d.input_names = input_names.empty() ? default_names(static_cast<int>(d.inputs.cols()),
                                                            learning::kDefaultInputs, "x")
                                            : std::move(input_names);
        d.output_names = output_names.empty() ? default_names(static_cast<int>(d.outputs.cols()),
                                                              learning::kDefaultOutputs, "y")
                                              : std::move(output_names);
        if (static_cast<int>(d.input_names.size()) != d.inputs.cols() ||
            static_cast<int>(d.output_names.size()) != d.outputs.cols())
          throw InputError("train: the names do not match the columns of x and y");
        learning::TrainOptions o;
        o.method = learning::parse_method(method);
        o.num_gaussians = num_gaussians;
        o.selection = learning::parse_selection(selection);
        o.max_gaussians = max_gaussians;
        o.restarts = restarts;
        o.seed = seed;
        o.em.reg_covar = reg_covar;
        o.validate();
        for (const auto& [name, value] : fixed)
          if (!std::isfinite(value))
            throw InputError(
                fmt::format("train: fixed '{}': expected a finite value, got {}", name, value));
        py::gil_scoped_release release;
        learning::Model model = learning::train(d, o);
        model.fixed = std::move(fixed);
        return model;
      },
      py::arg("x"), py::arg("y"), py::arg("method") = "gpr",
      py::arg("input_names") = std::vector<std::string>{},
      py::arg("output_names") = std::vector<std::string>{}, py::arg("num_gaussians") = 0,
      py::arg("selection") = std::string(learning::selection_name(kTrainDefaults.selection)),
      py::arg("max_gaussians") = kTrainDefaults.max_gaussians,
      py::arg("restarts") = kTrainDefaults.restarts, py::arg("seed") = kTrainDefaults.seed,
      py::arg("reg_covar") = kTrainDefaults.em.reg_covar,
      py::arg("fixed") = std::vector<std::pair<std::string, double>>{},
      "Trains a learner on inputs x (N, I) and outputs y (N, O). method: 'gpr' | 'gmr' | "
      "'joint-gmr'. Names "
      "default to xi_x, xi_y [m] and angle [rad], speed [m/s]. num_gaussians 0: chosen by "
      "`selection` "
      "('bic' | 'cv') up to max_gaussians. reg_covar: EM covariance regularisation (standardised "
      "units). "
      "fixed: constant quantities a player uses as they are, e.g. [('speed', 1.2)] for an "
      "angle-only data set "
      "(what `minigolf train` records from a constant column). Releases the GIL.");
  m.def(
      "load_dataset",
      [](const std::string& path, std::vector<std::string> inputs,
         std::vector<std::string> outputs) {
        const learning::Dataset d = learning::load_dataset(path, inputs, outputs);
        return py::make_tuple(matrix(d.inputs), matrix(d.outputs));
      },
      py::arg("path"), py::arg("inputs") = learning::kDefaultInputs,
      py::arg("outputs") = learning::kDefaultOutputs,
      "Reads a data set CSV: (x (N, I), y (N, O)) of the named columns");

  py::class_<ds::HittingModel>(m, "HittingModel", "The hitting DS model (SEDS + strength GMM).")
      .def_static(
          "load",
          [](const std::string& path) {
            return ds::read_hitting_model(system::resolve_data_path(path));
          },
          py::arg("path") = "data/models/hitting-default.json")
      .def_property_readonly(
          "x_star",
          [](const ds::HittingModel& h) {
            return std::array{h.x_star()[0], h.x_star()[1], h.x_star()[2]};
          },
          "Ball contact point x* [m, world]")
      .def_property_readonly("default_speed", &ds::HittingModel::default_speed, "v(x*) [m/s]")
      .def(
          "rollout",
          [](const ds::HittingModel& h, double angle, double speed, std::array<double, 3> start,
             const std::string& modulator, double dt, double max_duration) {
            ds::HittingCommand c;
            c.angle = angle;
            c.speed = speed;
            c.modulator = ds::parse_modulator(modulator);
            c.start = Eigen::Vector3d(start[0], start[1], start[2]);
            ds::RolloutOptions o;
            o.dt = dt;
            o.max_duration = max_duration;
            o.validate();
            ds::RolloutResult r;
            {
              py::gil_scoped_release release;
              r = ds::rollout(h, c, o);
            }
            const auto n = static_cast<py::ssize_t>(r.t.size());
            py::array_t<double> t(n), x({n, py::ssize_t{3}}), xd({n, py::ssize_t{3}});
            for (py::ssize_t i = 0; i < n; ++i) {
              t.mutable_data()[i] = r.t[static_cast<std::size_t>(i)];
              for (int j = 0; j < 3; ++j) {
                x.mutable_data()[i * 3 + j] = r.x[static_cast<std::size_t>(i)][j];
                xd.mutable_data()[i * 3 + j] = r.xdot[static_cast<std::size_t>(i)][j];
              }
            }
            py::dict d;
            d["reached"] = r.reached, d["stop_reason"] = r.stop_reason,
            d["position_error"] = r.position_error;
            d["duration"] = r.duration, d["steps"] = r.steps, d["t"] = t, d["x"] = x,
            d["xdot"] = xd;
            return d;
          },
          py::arg("angle"), py::arg("speed"), py::arg("start"), py::arg("modulator") = "constant",
          py::arg("dt") = 0.002, py::arg("max_duration") = 20.0,
          "Integrates the DS (RK4, step dt [s]) from `start` [m, world] for hitting angle [rad] "
          "and speed [m/s] "
          "until the ball is reached: dict with reached, stop_reason, position_error [m], duration "
          "[s], t (N,) [s], "
          "x (N, 3) [m], xdot (N, 3) [m/s]. Releases the GIL.");
}

}  // namespace mg::python
