#pragma once
// ispars.Client's shared pieces: the client every call and watch holds, and the conversions of
// the client library's answers to Python values.

#include <memory>

#include "ispars/client/client.hpp"
#include "python_module.hpp"

namespace ispars::python {

/// ispars.Client: the connection, shared by the Python object, its watches, and any call still
/// running after a Ctrl-C, so that the last of them closes it.
struct ClientHandle {
  std::shared_ptr<client::Client> client;
  client::Client* operator->() const { return client.get(); }
  client::Client& operator*() const { return *client; }
};

/// A reply as a dict: server_id, message, status (a SceneStatus).
py::dict reply_dict(const client::Reply& reply);

}  // namespace ispars::python
