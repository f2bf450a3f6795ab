// Demonstrations CSV (core/csv + ds/demonstrations), then the summary the fit starts from.
#include "core/csv.hpp"
#include "ds/demonstrations.hpp"
#include "harness.hpp"

MG_FUZZ_TARGET({
  const mg::CsvTable t = mg::parse_csv(mg::fuzz::as_text(data, size), "fuzz.csv");
  const auto demos = mg::ds::demonstrations_from_table(t);
  (void)mg::ds::summarize_demonstrations(demos, 0.02);
})
