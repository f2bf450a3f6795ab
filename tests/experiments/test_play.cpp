// Sweeps, collection (interrupted and resumed), evaluation: determinism over threads, the file
// format, and a small collect -> train -> evaluate chain.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "../slow_test.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "experiments/collect.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/reproduce.hpp"
#include "experiments/sweep.hpp"
#include "learning/dataset.hpp"

namespace mg::experiments {
namespace {

namespace fs = std::filesystem;

const system::System& flat() {
  static const system::System s(system::load_config("", "flat"));
  return s;
}

std::string slurp(const fs::path& p) { return read_text_file(p); }

fs::path temp(const std::string& name) {
  return fs::temp_directory_path() / ("mg_play_" + std::to_string(::getpid()) + "_" + name);
}

TEST(Sweep, CellsAreThePuttsAndDoNotDependOnTheThreadCount) {
  SweepOptions o;
  o.hole = {1.5, 0.0};
  o.angles = linspace(-0.02, 0.02, 3);
  o.speeds = linspace(1.6, 2.2, 3);
  o.ball_only = true;
  o.threads = 1;
  const auto one = run_sweep(flat(), o);
  o.threads = 2;
  const auto two = run_sweep(flat(), o);
  EXPECT_EQ(sweep_csv(one), sweep_csv(two));
  ASSERT_EQ(one.size(), 9u);
  system::SystemData d(flat());
  const auto direct = system::ball_putt(flat(), d, o.hole, one[5].angle, one[5].speed);
  EXPECT_EQ(direct.closest_approach, one[5].outcome.closest_approach);
  EXPECT_EQ(one[5].angle, 0.0);
  EXPECT_EQ(one[5].speed, 2.2);
  const auto header = sweep_csv(one).substr(0, sweep_csv(one).find('\n'));
  EXPECT_EQ(header.rfind("angle,speed,sunk,closest_approach,rest_x,rest_y", 0), 0u) << header;
}

TEST(Sweep, FullSystemCellsMatchArmPutts) {
  SweepOptions o;
  o.hole = {2.0, 0.0};
  o.angles = {0.01};
  o.speeds = {1.6};
  const auto cells = run_sweep(flat(), o);
  system::SystemData d(flat());
  const auto r = system::arm_putt(flat(), d, o.hole, 0.01, 1.6);
  EXPECT_EQ(cells[0].outcome.sunk, r.outcome.sunk);
  EXPECT_EQ(cells[0].launch_speed, r.launch.speed);
}

std::vector<std::array<double, 2>> holes() {
  return {{2.0, -0.1}, {2.0, 0.1}, {2.0, 0.3}, {2.5, 0.0}};
}

CollectOptions angle_only(double speed) {
  CollectOptions o;
  o.teacher.strategy = teacher::Strategy::kMinAngle;
  o.teacher.learn_speed = false;
  o.teacher.fixed_speed = speed;
  o.teacher.max_full_putts = 10;
  return o;
}

TEST(Collect, SameBitsWithOneAndTwoThreadsAndUnplayableSituationsAreRecorded) {
  const auto a = temp("c1.csv"), b = temp("c2.csv");
  CollectOptions o = angle_only(1.55);
  o.threads = 1;
  const auto r1 = collect(flat(), holes(), o, a);
  o.threads = 2;
  collect(flat(), holes(), o, b);
  EXPECT_EQ(slurp(a), slurp(b));
  ASSERT_EQ(r1.examples.size(), 4u);
  EXPECT_TRUE(r1.examples[0].found && r1.examples[1].found && r1.examples[2].found);
  EXPECT_FALSE(r1.examples[3].found);  // 2.5 m at 1.55 m/s club speed: the ball stops short
  const std::string text = slurp(a);
  EXPECT_NE(text.find("# unplayable: index=3"), std::string::npos) << text;
  // The file trains as it is: comment lines are skipped, the fixed speed is a constant column.
  const CsvTable t = read_csv(a);
  EXPECT_EQ(t.num_rows(), 3u);
  const auto fixed = learning::constant_columns(t, {"speed"}, {"xi_y", "angle"});
  ASSERT_EQ(fixed.size(), 1u);
  EXPECT_EQ(fixed[0].second, 1.55);
  fs::remove(a);
  fs::remove(b);
}

TEST(Collect, AnInterruptedCollectionResumesWithoutLosingOrDuplicatingAnExample) {
  const auto full = temp("full.csv"), part = temp("part.csv");
  CollectOptions o = angle_only(1.55);
  collect(flat(), holes(), o, full);
  // Interrupted after two situations: the file as it was then (settings, header, two rows).
  std::istringstream in(slurp(full));
  std::string line, cut;
  for (int k = 0; k < 4 && std::getline(in, line); ++k) cut += line + "\n";
  write_file_atomic(part, cut);
  o.resume = true;
  const auto r = collect(flat(), holes(), o, part);
  EXPECT_EQ(r.resumed, 2);
  EXPECT_EQ(slurp(part), slurp(full));
  // Resuming a finished file changes nothing; other settings are refused.
  const auto again = collect(flat(), holes(), o, part);
  EXPECT_EQ(again.resumed, 4);
  EXPECT_EQ(slurp(part), slurp(full));
  CollectOptions other = angle_only(1.6);
  other.resume = true;
  EXPECT_THROW(collect(flat(), holes(), other, part), InputError);
  EXPECT_EQ(slurp(part), slurp(full));  // refused without touching the file
  fs::remove(full);
  fs::remove(part);
}

TEST(Evaluate, WilsonIntervalMatchesTheClosedForm) {
  const auto a = wilson_interval(30, 30);
  EXPECT_NEAR(a[0], 0.8865, 1e-4);  // 30/30: [0.8865, 1]
  EXPECT_DOUBLE_EQ(a[1], 1.0);
  const auto b = wilson_interval(26, 30);
  EXPECT_NEAR(b[0], 0.7028, 1e-3);
  EXPECT_NEAR(b[1], 0.9469, 1e-3);
  const auto c = wilson_interval(0, 10);
  EXPECT_DOUBLE_EQ(c[0], 0.0);
  EXPECT_NEAR(c[1], 0.2775, 1e-3);
}

TEST(Evaluate, CollectTrainEvaluateOnASmallCase) {
  const auto data = temp("train.csv");
  const field::Situations line =
      field::parse_situations_spec("line:2.0,-0.1:2.0,0.3:5", flat().field().situations);
  CollectOptions o = angle_only(1.55);
  collect(flat(), line.collection_points(), o, data);
  const CsvTable t = read_csv(data);
  ASSERT_EQ(t.num_rows(), 5u);
  learning::TrainOptions to;
  learning::Model model = learning::train(learning::dataset_from_table(t, {"xi_y"}, {"angle"}), to);
  model.fixed = learning::constant_columns(t, {"speed"}, {"xi_y", "angle"});
  EvaluateOptions eo;
  eo.situations = 6;
  eo.seed = 3;
  eo.threads = 1;
  eo.teacher = o.teacher;
  const Evaluation e1 = evaluate_model(flat(), model, line, eo);
  eo.threads = 2;
  const Evaluation e2 = evaluate_model(flat(), model, line, eo);
  EXPECT_EQ(evaluation_csv(e1, flat().field()), evaluation_csv(e2, flat().field()));
  EXPECT_GE(e1.sunk, 5) << evaluation_csv(
      e1, flat().field());  // flat: interpolation between 5 examples
  EXPECT_EQ(e1.oracle_found, 6);
  EXPECT_DOUBLE_EQ(e1.oracle_ceiling, 1.0);
  EXPECT_LE(e1.ci95[0], e1.success_ratio);
  for (const auto& r : e1.rows) EXPECT_EQ(r.predicted.speed, 1.55);
  // A slower green and a weaker arm that the robot believes in: the fixed speed is played as the
  // arrival speed it gave on the survey (docs/belief.md), the same bits on any thread count.
  plant::Plant slow;
  slow.field.rolling_resistance_scale = 1.12;
  slow.arm.club_speed_scale = 0.97;
  const system::System aware(system::load_config("", "flat"), slow, slow);
  eo.oracle = false;
  eo.threads = 1;
  const Evaluation b1 = evaluate_model(aware, model, line, eo);
  eo.threads = 2;
  const Evaluation b2 = evaluate_model(aware, model, line, eo);
  EXPECT_EQ(evaluation_csv(b1, aware.field()), evaluation_csv(b2, aware.field()));
  for (const auto& r : b1.rows) EXPECT_GT(r.predicted.speed, 1.55 / 0.97);
  EXPECT_GE(b1.sunk, 5) << evaluation_csv(b1, aware.field());
  fs::remove(data);
}

// A flat lane is translation-invariant, so a model of xi = hole - ball learned from the
// tee plays from balls it never saw; collect writes the ball of each example.
TEST(Evaluate, AFlatModelLearnedFromTheTeePlaysFromAnywhere) {
  const auto data = temp("tee.csv");
  const field::Field& f = flat().field();
  const field::Situations tee_holes =
      field::parse_situations_spec("grid:1.5,2.2:-0.2,0.3:3,3", f.situations);
  CollectOptions o;
  o.threads = 2;
  collect(flat(), tee_holes.collection_points(), o, data);
  const CsvTable t = read_csv(data);
  ASSERT_GE(t.num_rows(), 8u);
  EXPECT_THROW(t.column_index("ball_x"), InputError);  // every ball on the tee: no ball columns
  const learning::Model model =
      learning::train(learning::dataset_from_table(t, {"xi_x", "xi_y"}, {"angle", "speed"}),
                      learning::TrainOptions{});

  field::Situations anywhere =
      field::parse_situations_spec("box:1.75,2.15:-0.1,0.2:2,2", f.situations);
  field::Region balls;
  balls.shape = field::RegionShape::kBox;
  balls.x_range = {0.0, 0.3};
  balls.y_range = {-0.1, 0.1};
  balls.counts = {2, 2};
  anywhere.balls = balls;
  anywhere.validate(f, "test");
  EXPECT_EQ(anywhere.learner_inputs(), (std::vector<std::string>{"xi_x", "xi_y"}));
  EvaluateOptions eo;
  eo.situations = 8;
  eo.seed = 5;
  eo.oracle = false;
  const Evaluation e = evaluate_model(flat(), model, anywhere, eo);
  int off_tee = 0;
  for (const auto& r : e.rows) off_tee += r.ball != f.tee;
  EXPECT_EQ(off_tee, 8);
  EXPECT_GE(e.sunk, 7) << evaluation_csv(e, f);
  const CsvTable rows = parse_csv(evaluation_csv(e, f), "evaluation");
  const auto bx = rows.column_index("ball_x");
  const auto xi = rows.column_index("xi_x");
  const auto hx = rows.column_index("hole_x");
  for (const auto& row : rows.rows) EXPECT_DOUBLE_EQ(row[xi], row[hx] - row[bx]);

  // Collecting from balls off the tee: the file has the balls, xi is hole - ball.
  const auto from_balls = temp("balls.csv");
  const std::vector<field::Situation> two{{{0.2, 0.1}, {2.0, 0.1}}, {{0.3, -0.1}, {1.9, 0.0}}};
  collect(flat(), two, o, from_balls);
  const CsvTable b = read_csv(from_balls);
  ASSERT_EQ(b.num_rows(), 2u);
  EXPECT_EQ(b.rows[0][b.column_index("ball_x")], 0.2);
  EXPECT_EQ(b.rows[1][b.column_index("ball_y")], -0.1);
  EXPECT_NEAR(b.rows[1][b.column_index("xi_x")], 1.6, 1e-12);
  fs::remove(data);
  fs::remove(from_balls);
}

TEST(Evaluate, ModelsThatCannotPlayAreRefused) {
  learning::Model m;
  m.input_names = {"distance"};
  m.output_names = {"angle"};
  EXPECT_THROW(check_playable_model(m, "m.json"), InputError);
  m.input_names = {"xi_y"};
  EXPECT_THROW(check_playable_model(m, "m.json"), InputError);  // no speed, no fixed speed
  m.fixed = {{"speed", 1.5}};
  EXPECT_NO_THROW(check_playable_model(m, "m.json"));
  m.output_names = {"speed"};
  EXPECT_THROW(check_playable_model(m, "m.json"), InputError);  // no angle
}

TEST(Reproduce, ArctanSplitKeepsTheCornersInTraining) {
  for (std::uint64_t seed = 0; seed < 50; ++seed) {
    const auto v = arctan_validation_split(7, 4, 9, seed);
    ASSERT_EQ(v.size(), 9u);
    for (int i : v) EXPECT_TRUE(i != 0 && i != 3 && i != 24 && i != 27) << i;
    for (std::size_t k = 1; k < v.size(); ++k) EXPECT_LT(v[k - 1], v[k]);
  }
  EXPECT_NE(arctan_validation_split(7, 4, 9, 1), arctan_validation_split(7, 4, 9, 2));
}

// The whole chain on one field: the same CSVs (data, models, predictions, evaluations, curves,
// sweeps) with 1 and 2 threads.
TEST(Reproduce, SameCsvFilesWithOneAndTwoThreads) {
  MG_SLOW_TEST();
  ReproduceOptions o;
  o.quick = true;
  o.fields = {"flat"};
  o.plots = false;
  // The thesis's tables only: the parts beyond it have thread-count tests of their own (self-teach,
  // curves, rounds), and with them this test took 10 minutes on a loaded machine.
  o.beyond = false;
  o.real_robot = false;
  o.round_seeds = 0;
  o.threads = 1;
  o.out = temp("repro1");
  reproduce(o, [](const std::string&) {});
  // Two threads, and a belief that is the identity (the field files as they are): the same bits.
  o.threads = 2;
  o.out = temp("repro2");
  fs::create_directories(o.out);
  o.belief = (o.out / "identity-belief.yaml").string();
  write_file_atomic(o.belief, "format_version: 1\n");
  reproduce(o, [](const std::string&) {});
  int files = 0;
  for (const auto& entry : fs::directory_iterator(temp("repro1") / "csv")) {
    const auto other = temp("repro2") / "csv" / entry.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_EQ(slurp(entry.path()), slurp(other)) << entry.path().filename();
    ++files;
  }
  EXPECT_GT(files, 10);
  const std::string report = slurp(temp("repro1") / "report.md");
  EXPECT_NE(report.find("| flat | gpr | 30 |"), std::string::npos) << report;
  EXPECT_NE(report.find("thesis"), std::string::npos);
  fs::remove_all(temp("repro1"));
  fs::remove_all(temp("repro2"));
}

TEST(Reproduce, ABadBeliefFileIsRefusedBeforeAnyStep) {
  ReproduceOptions o;
  o.out = temp("repro-belief");
  o.fields = {"flat"};
  o.plots = false;
  o.belief = (temp("repro-belief-in") / "missing.yaml").string();
  int steps = 0;
  EXPECT_THROW(reproduce(o, [&](const std::string&) { ++steps; }), InputError);
  EXPECT_EQ(steps, 0);
  fs::remove_all(o.out);
}

TEST(Reproduce, FailsClearlyOnAMissingDataSet) {
  ReproduceOptions o;
  o.out = temp("repro");
  o.datasets = temp("no-such-folder");
  o.fields = {"flat"};
  o.plots = false;
  try {
    reproduce(o, [](const std::string&) {});
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("flat.csv"), std::string::npos) << e.what();
  }
  fs::remove_all(o.out);
}

}  // namespace
}  // namespace mg::experiments
