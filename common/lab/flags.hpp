#pragma once
// Flags that several lab subcommands share, with the checks the recipe declares: method and
// rule-set names (build_recipe.hpp's lists), and the stretch slack with the recipe's own ranges.

#include <CLI/CLI.hpp>

#include <cstdint>

namespace ispars::lab {

struct ExperimentOptions;

/// Accepts a build method name (dense, spars, ispars, irisc, ispars2), naming the others if not.
[[nodiscard]] CLI::Validator build_method_check();
/// Accepts a SPARS rule set name (stretch, alg1), naming the others if not.
[[nodiscard]] CLI::Validator spars_variant_check();
/// --stretch-slack and --stretch-slack-after, with the recipe's ranges.
void add_stretch_slack_options(CLI::App& command, double& slack, std::uint64_t& after);
/// --scenes, --threads and --json, which every experiment takes.
void add_experiment_flags(CLI::App& command, ExperimentOptions& options);

}  // namespace ispars::lab
