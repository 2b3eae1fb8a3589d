// Compiled, never run: a program that only uses the service includes the client's public headers
// without the wire's generated messages (this target has no path to them) or any Fast DDS header,
// and the example of docs/service.md ("The C++ client library") compiles against them.

#include <chrono>
#include <iostream>

#include "ispars/client/client.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/client/types.hpp"

#if defined(_FASTDDS_DOMAIN_PARTICIPANT_HPP_) || defined(_FASTDDS_DDS_QOS_QOSPOLICIES_HPP_) || \
    defined(_FAST_DDS_GENERATED_ISPARS_MSG_ISPARS_H_)
#error "a public client header includes a Fast DDS header or the wire's messages"
#endif

namespace ispars::client {

// docs/service.md's example, line for line.
[[maybe_unused]] void docs_service_example() {
  ispars::client::ClientOptions options;
  options.participant.domain = 0;
  ispars::client::Client client(options);
  client.load("tower");
  ispars::client::BuildArgs build;  // method ispars, seed 1
  build.samples = 20000;
  client.build("tower", build);
  const ispars::client::SceneStatus built = client.wait_idle("tower", {}, std::chrono::minutes(10));
  const ispars::client::TourReply tour = client.tour("tower", 5.0, 1, {});
  std::cout << built.vertices << " vertices; tour " << tour.tour.cost << " >= " << tour.tour.lower_bound << "\n";
}

}  // namespace ispars::client
