#pragma once
// Each subcommand registers itself on the CLI11 app and returns what main should run.
#include <functional>

namespace CLI { class App; }

namespace millwear::app {

using Action = std::function<int()>;  // returns the exit code

// Every register_* adds a subcommand; when it is chosen, *action is set.
void register_profile(CLI::App& app, Action* action);
void register_charge(CLI::App& app, Action* action);
void register_run(CLI::App& app, Action* action);
void register_animate(CLI::App& app, Action* action);
void register_rule1(CLI::App& app, Action* action);
void register_tradeoff(CLI::App& app, Action* action);
void register_validate(CLI::App& app, Action* action);
void register_calibrate(CLI::App& app, Action* action);
void register_hardness(CLI::App& app, Action* action);
void register_screen(CLI::App& app, Action* action);
void register_screen_task(CLI::App& app, Action* action);
void register_sweep(CLI::App& app, Action* action);
void register_view(CLI::App& app, Action* action);

}  // namespace millwear::app
