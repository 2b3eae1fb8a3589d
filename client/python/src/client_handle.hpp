#pragma once
// ispars.Client's shared pieces: the client every call and watch holds, and the conversions of
// the client library's answers to Python values.

#include <memory>
#include <stdexcept>

#include "ispars/client/client.hpp"
#include "python_module.hpp"

namespace ispars::python {

/// ispars.Client: the connection, shared by the Python object, its watches, and any call still
/// running after a Ctrl-C, so that the last of them closes it.
/// close() empties the Python object's handle; a call on it then raises RuntimeError.
struct ClientHandle {
  std::shared_ptr<client::Client> client;
  client::Client* operator->() const { return &**this; }
  client::Client& operator*() const {
    if (!client) throw std::runtime_error("this Client is closed (close() was called or its with-block ended)");
    return *client;
  }
};

/// A reply as a dict: server_id, message, status (a SceneStatus).
py::dict reply_dict(const client::Reply& reply);

}  // namespace ispars::python
