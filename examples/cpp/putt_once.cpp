// One putt with the minigolf C++ API: load a field, build the system (the field's world with the
// WAM and its club, the hitting model, the control module), let the arm hit the ball once and
// print where it went.
//
//   putt_once [FIELD [ANGLE SPEED]]     FIELD: shipped name or field file (flat);
//                                       ANGLE [rad] hitting angle (0.02), SPEED [m/s] club (1.2)
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

#include <minigolf/minigolf.hpp>

namespace {

double number(const char* text, const char* what) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0') throw mg::InputError(std::string(what) + ": expected a number");
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc != 1 && argc != 2 && argc != 4)
      throw mg::InputError("usage: putt_once [FIELD [ANGLE SPEED]]");
    // The field the robot believes in: its hole, its tee, its surface.
    const std::string name = argc > 1 ? argv[1] : "flat";
    const mg::field::Field field = mg::field::load_field(name);
    // The system: module configuration (defaults, this field), worlds, hitting model, module.
    const mg::system::System sys(mg::system::load_config("", name), field);
    mg::system::SystemData data(sys);  // this thread's simulation state

    mg::system::PuttSpec spec;  // the hole where the field has it, the ball on the tee
    spec.angle = argc > 2 ? number(argv[2], "ANGLE") : 0.02;  // [rad] in the base's frame
    spec.speed = argc > 3 ? number(argv[3], "SPEED") : 1.2;   // [m/s] club speed at the ball
    const mg::system::PuttReport r = mg::system::putt(sys, data, spec);

    const mg::sim::PuttOutcome& out = r.outcome;
    std::cout << field.name << ": club " << r.club.speed << " m/s -> ball " << r.launch.speed
              << " m/s; " << (out.sunk ? "sunk" : "missed") << ", rest (" << out.rest_position[0]
              << ", " << out.rest_position[1] << ") m, closest approach " << out.closest_approach
              << " m\n";
    std::cout << mg::system::putt_json(sys, spec, r).dump() << '\n';  // as `minigolf putt --json`
    return 0;
  } catch (const mg::InputError& e) {  // bad input: one line, exit 2 (as `minigolf`)
    std::cerr << "putt_once: error: " << e.what() << '\n';
    return 2;
  } catch (const mg::IoError& e) {
    std::cerr << "putt_once: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "putt_once: error: " << e.what() << '\n';
    return 1;
  }
}
