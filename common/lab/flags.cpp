#include "flags.hpp"

#include "commands.hpp"
#include "ispars/params/cli_archive.hpp"
#include "ispars/roadmap/build_recipe.hpp"

namespace ispars::lab {

CLI::Validator build_method_check() {
  return CLI::Validator(
      [](std::string& text) {
        return parse_build_method(text) ? std::string()
                                        : "unknown method '" + text + "' (" + build_method_names() + ")";
      },
      "dense|spars|ispars|irisc|ispars2");
}

CLI::Validator spars_variant_check() {
  return CLI::Validator(
      [](std::string& text) {
        return parse_spars_variant(text) ? std::string()
                                         : "unknown variant '" + text + "' (" + spars_variant_names() + ")";
      },
      "stretch|alg1");
}

void add_stretch_slack_options(CLI::App& command, double& slack, std::uint64_t& after) {
  params::add_flag(command, kStretchSlack, slack);
  params::add_flag(command, kStretchSlackAfter, after);
}

void add_experiment_flags(CLI::App& command, ExperimentOptions& options) {
  command.add_option("--scenes", options.scenes_dir, "Directory of the scene YAML files");
  command.add_option("--threads", options.threads, "Threads per build")->check(CLI::Range(1u, 64u));
  command.add_flag("--json", options.json, "Print one JSON object as the last line of stdout");
}

}  // namespace ispars::lab
