#pragma once
/// The experiments' results in the process-to-process byte format (system/wire.hpp), so their
/// job loops can run over MPI processes (system::distributed_for). The size checks catch a
/// field added to a struct without adding it here (x86-64 layouts).
#include "experiments/evaluate.hpp"
#include "experiments/launch_study.hpp"
#include "experiments/learning_curves.hpp"
#include "experiments/sweep.hpp"
#include "system/wire.hpp"
#include "teacher/teacher.hpp"

namespace mg::system {

template <>
struct Wire<teacher::Example> {
  static_assert(sizeof(teacher::Example) == 104,
                "teacher::Example changed: update Wire<teacher::Example>");
  template <typename A>
  static void fields(A& a, teacher::Example& e) {
    a(e.hole, e.ball, e.found, e.angle, e.speed, e.margin_angle, e.margin_speed, e.launch_angle,
      e.launch_speed, e.approach_speed, e.full_putts, e.ball_putts);
  }
};

template <>
struct Wire<experiments::SweepCell> {
  static_assert(sizeof(experiments::SweepCell) == 136, "SweepCell changed: update Wire<SweepCell>");
  template <typename A>
  static void fields(A& a, experiments::SweepCell& c) {
    a(c.angle, c.speed, c.hit, c.outcome, c.launch_angle, c.launch_speed);
  }
};

template <>
struct Wire<experiments::Prediction> {
  static_assert(sizeof(experiments::Prediction) == 32,
                "Prediction changed: update Wire<Prediction>");
  template <typename A>
  static void fields(A& a, experiments::Prediction& p) {
    a(p.angle, p.speed, p.angle_std, p.speed_std);
  }
};

template <>
struct Wire<experiments::SituationResult> {
  static_assert(sizeof(experiments::SituationResult) == 184,
                "SituationResult changed: update Wire<SituationResult>");
  template <typename A>
  static void fields(A& a, experiments::SituationResult& r) {
    a(r.hole, r.ball, r.predicted, r.in_envelope, r.sunk, r.outcome, r.oracle_found,
      r.oracle_full_putts, r.oracle_ball_putts);
  }
};

template <>
struct Wire<experiments::LaunchHit> {
  static_assert(sizeof(experiments::LaunchHit) == 160, "LaunchHit changed: update Wire<LaunchHit>");
  template <typename A>
  static void fields(A& a, experiments::LaunchHit& h) {
    a(h.angle_index, h.hit_index, h.commanded_angle_deg, h.commanded_speed, h.seed, h.hit,
      h.ball_start, h.club_angle, h.club_speed, h.launch_angle, h.launch_speed, h.launch_error_deg,
      h.club_speed_error, h.launch_club_ratio, h.faulted, h.rest_time, h.failure);
  }
};

template <>
struct Wire<experiments::CurveRun> {
  static_assert(sizeof(experiments::CurveRun) == 64, "CurveRun changed: update Wire<CurveRun>");
  template <typename A>
  static void fields(A& a, experiments::CurveRun& r) {
    a(r.learner, r.run, r.putts, r.sunk, r.situations, r.examples);
  }
};

}  // namespace mg::system
