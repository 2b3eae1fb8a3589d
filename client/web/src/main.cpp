// ispars-web: the live viewer's gateway. Follows scenes over DDS as a replica, like `ispars
// watch`, and serves a page (three.js) over HTTP and WebSocket to the browsers its access policy
// lets in (client/web/README.md). Binds to 127.0.0.1 unless told otherwise.

#include <signal.h>

#include <iostream>

#include "ispars/client/client.hpp"
#include "web_cli.hpp"
#include "web_server.hpp"

int main(int argc, char** argv) {
  ispars::web::WebCommandLine command_line;
  if (const int exit_code = ispars::web::parse_command_line(argc, argv, command_line); exit_code >= 0) return exit_code;
  const auto& options = command_line.server;

  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  ::signal(SIGPIPE, SIG_IGN);  // a browser that goes away mid-write is an error code, not a signal

  try {
    ispars::client::Client client(command_line.client);
    ispars::web::WebServer server(client, options);
    std::cout << "ispars-web: serving http://" << options.address << ":" << server.port() << "/ (DDS domain "
              << command_line.domain << ", web root " << options.web_root.string() << ", "
              << (options.access.token.empty() ? "no token" : "a token required") << ", "
              << options.access.allowed_origins.size() << " more origins allowed)" << std::endl;
    int signal = 0;
    sigwait(&stop_signals, &signal);
    const auto stats = server.stats();
    std::cout << "ispars-web: stopping (" << stats.browsers_total << " browsers served, " << stats.messages_sent
              << " messages sent, " << stats.refused_access << " requests refused by Host, Origin or token, "
              << stats.tours_refused << " tours refused over --max-tours, " << stats.evicted
              << " idle connections closed to make room, " << stats.unread << " browsers closed for not reading)"
              << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "ispars-web: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
