#include "ispars/cli_app/cli_app.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "ispars/wire/participant.hpp"

#include <cctype>
#include <iostream>

#include "ispars/params/cli_archive.hpp"
#include "ispars/wire/participant_options.hpp"

namespace ispars::cli_app {
namespace {

// Where the daemons are and who this client is: flags, or ISPARS_* environment variables. The
// participant's flags are its declared settings (participant_options.hpp), as the daemon's are.
struct ConnectionArgs {
  wire::ParticipantOptions participant;
  double timeout_s = 15;
  std::string server;

  void add(CLI::App& app) {
    params::visit(participant, [&](const auto& spec, auto& member) {
      std::string env = "ISPARS_" + std::string(spec.name);  // ISPARS_DOMAIN, ISPARS_PROFILE_FILE, ...
      for (char& c : env) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      params::add_flag(app, spec, member)->envname(env);
    });
    app.add_option("--timeout", timeout_s, "seconds to wait for a daemon and each reply")->check(CLI::PositiveNumber);
    app.add_option("--server", server, "the daemon to load a scene on, when several offer it");
  }
  [[nodiscard]] client::ClientOptions options() const {
    client::ClientOptions o;
    o.server = server;
    o.participant = participant;
    o.participant.name = "ispars cli";
    o.timeout = std::chrono::milliseconds(static_cast<long>(timeout_s * 1000));
    return o;
  }
};

// The chosen command, checked; nullptr when parsing ended the run (help), with `code` set.
Command* parse(CLI::App& app, int argc, char** argv, const std::vector<std::unique_ptr<Command>>& commands, int& code) {
  std::vector<CLI::App*> subcommands;
  for (const auto& c : commands) subcommands.push_back(c->add(app));
  try {
    app.parse(argc, argv);
    for (std::size_t i = 0; i < commands.size(); ++i) {
      if (subcommands[i]->parsed()) {
        commands[i]->check();
        return commands[i].get();
      }
    }
    code = 0;  // require_subcommand(1): not reached
  } catch (const CLI::CallForHelp& e) {
    code = app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    code = app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ispars: " << e.what() << " (see --help)\n";
    code = 2;
  }
  return nullptr;
}

}  // namespace

int run_cli(int argc, char** argv, const char* title, const std::vector<std::unique_ptr<Command>>& commands) {
  // Warnings from the client library (a peer dropped under DDS Security, say) go to stderr, never
  // into the command's output (--json included).
  spdlog::set_default_logger(spdlog::stderr_color_mt("ispars"));
  // Fast DDS's own log (a bad profiles file's XML errors, say) through the same logger, one plain
  // line each, instead of its coloured console output; undone before the loggers go.
  wire::route_fastdds_log_to_spdlog(/*warnings=*/false);
  struct StopRouting {
    ~StopRouting() { wire::stop_fastdds_log_routing(); }
  } stop_routing;
  CLI::App app{title};
  app.require_subcommand(1);
  ConnectionArgs connection;
  connection.add(app);
  int code = 0;
  Command* chosen = parse(app, argc, argv, commands, code);
  if (chosen == nullptr) return code;
  try {
    if (const auto delegated = chosen->run_elsewhere(argc, argv)) return *delegated;
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

}  // namespace ispars::cli_app
