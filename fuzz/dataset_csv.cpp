// Learning data set CSV (core/csv + learning/dataset), then a tiny GMR fit on what parsed.
#include "core/csv.hpp"
#include "harness.hpp"
#include "learning/dataset.hpp"
#include "learning/learner.hpp"

MG_FUZZ_TARGET({
  const mg::CsvTable t = mg::parse_csv(mg::fuzz::as_text(data, size), "fuzz.csv");
  const auto d = mg::learning::dataset_from_table(t, {"xi_x", "xi_y"}, {"angle"});
  if (d.size() >= 2 && d.size() <= 64) {
    mg::learning::TrainOptions o;
    o.method = mg::learning::Method::kGmr;
    o.num_gaussians = 1;
    o.restarts = 1;
    o.choose_reg_covar = false;
    (void)mg::learning::train(d, o);
  }
})
