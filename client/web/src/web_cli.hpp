#pragma once
// ispars-web's command line: every flag declared once with its range and doc, and the checks
// that need more than one flag (a non-loopback address needs a token) made before DDS is joined.

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "ispars/client/client.hpp"
#include "web_server.hpp"

namespace ispars::web {

/// What the command line gives.
struct WebCommandLine {
  WebServerOptions server;
  client::ClientOptions client;
  int domain = 0;
};

/// Parses argv: the options, or the exit status (2 on a bad command line, 0 after --help) with
/// the message already printed.
[[nodiscard]] int parse_command_line(int argc, char** argv, WebCommandLine& out);

}  // namespace ispars::web
