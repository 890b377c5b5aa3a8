// millwear command line: the only place that prints to the terminal.
// Exit codes: 0 success, 1 a run that failed, 2 bad input (scene, profile or command line).
#include <CLI/CLI.hpp>

#include <iostream>

#include "app/commands.hpp"
#include "common/errors.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT

int main(int argc, char** argv) {
  CLI::App app{"millwear: lifter wear in grinding mills by DEM and Archard's law (2D slice)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("millwear ") + MILLWEAR_VERSION +
                                        " (commit " + MILLWEAR_COMMIT + ")");
  millwear::app::Action action;
  millwear::app::register_profile(app, &action);
  millwear::app::register_charge(app, &action);
  millwear::app::register_run(app, &action);
  millwear::app::register_animate(app, &action);
  millwear::app::register_rule1(app, &action);
  millwear::app::register_tradeoff(app, &action);
  millwear::app::register_validate(app, &action);
  millwear::app::register_calibrate(app, &action);
  millwear::app::register_hardness(app, &action);
  millwear::app::register_screen(app, &action);
  millwear::app::register_screen_task(app, &action);
  millwear::app::register_sweep(app, &action);
  millwear::app::register_view(app, &action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;  // bad command line is bad input
  }
  try {
    return action ? action() : 2;
  } catch (const millwear::InputError& e) {
    std::cerr << "millwear: error: " << e.what() << "\n";
    return 2;
  } catch (const millwear::RunError& e) {
    std::cerr << "millwear: run failed: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "millwear: run failed: " << e.what() << "\n";
    return 1;
  }
}
