// `ispars`: the command-line client of isparsd. The connection's options live here; each
// subcommand lives in a file of its own (commands.hpp).

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <iostream>

#include "commands.hpp"
#include "ispars/client/client.hpp"

namespace ispars::cli {

std::vector<std::unique_ptr<Command>> all_commands() {
  std::vector<std::unique_ptr<Command>> out;
  for (auto* make : {make_scenes_command, make_build_command, make_extend_command, make_cancel_command,
                     make_stats_command, make_drop_command, make_verify_command, make_path_command,
                     make_watch_command, make_tour_command, make_snapshot_command, make_render_command}) {
    out.push_back(make());
  }
  return out;
}

namespace {

// Where the daemons are and who this client is: flags, or ISPARS_* environment variables.
struct ConnectionArgs {
  int domain = 0;
  double timeout_s = 15;
  std::string profile_file, profile_name = "ispars", security, server;

  void add(CLI::App& app) {
    app.add_option("--domain", domain, "DDS domain id")->envname("ISPARS_DOMAIN")->check(CLI::Range(0, 232));
    app.add_option("--profile-file", profile_file, "Fast DDS XML profiles file (default: built-in localhost only)")
        ->envname("ISPARS_PROFILE_FILE");
    app.add_option("--profile-name", profile_name, "participant profile in the profiles file");
    app.add_option("--security", security,
                   "DDS Security identity directory (deploy/security/make-keystore.sh); default: no security")
        ->envname("ISPARS_SECURITY");
    app.add_option("--timeout", timeout_s, "seconds to wait for a daemon and each reply")->check(CLI::PositiveNumber);
    app.add_option("--server", server, "the daemon to load a scene on, when several offer it");
  }
  [[nodiscard]] client::ClientOptions options() const {
    client::ClientOptions o;
    o.server = server;
    o.participant.domain = domain;
    o.participant.profile_file = profile_file;
    o.participant.profile_name = profile_name;
    o.participant.security = security;
    o.participant.name = "ispars cli";
    o.timeout = std::chrono::milliseconds(static_cast<long>(timeout_s * 1000));
    return o;
  }
};

// Exit codes: 0 done, 1 refused or failed (a rejected or forbidden request, a failed job, an
// invalid tour), 2 bad arguments, 3 no daemon or no reply.
int run(int argc, char** argv) {
  CLI::App app{"ispars: client of the isparsd roadmap service"};
  app.require_subcommand(1);
  ConnectionArgs connection;
  connection.add(app);
  const std::vector<std::unique_ptr<Command>> commands = all_commands();
  std::vector<CLI::App*> subcommands;
  for (const auto& c : commands) subcommands.push_back(c->add(app));
  Command* chosen = nullptr;
  try {
    app.parse(argc, argv);
    for (std::size_t i = 0; i < commands.size(); ++i) {
      if (subcommands[i]->parsed()) chosen = commands[i].get();
    }
    if (chosen != nullptr) chosen->check();
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ispars: " << e.what() << " (see --help)\n";
    return 2;
  }
  try {
    if (chosen == nullptr) return 0;  // require_subcommand(1): not reached
    client::Client client(connection.options());
    return chosen->run(client);
  } catch (const client::ClientError& e) {
    std::cerr << "ispars: " << e.what() << "\n";
    const auto kind = e.kind();
    return kind == client::ClientError::Kind::rejected || kind == client::ClientError::Kind::forbidden ? 1 : 3;
  } catch (const CLI::ValidationError& e) {
    std::cerr << "ispars: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ispars: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace
}  // namespace ispars::cli

int main(int argc, char** argv) {
  // Warnings from the client library (a peer dropped under DDS Security, say) go to stderr, never
  // into the command's output (--json included).
  spdlog::set_default_logger(spdlog::stderr_color_mt("ispars"));
  return ispars::cli::run(argc, argv);
}
