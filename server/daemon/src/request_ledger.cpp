#include "ispars/server/request_ledger.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "ispars/wire/convert.hpp"

namespace ispars::server {

RequestLedger::RequestLedger(const std::filesystem::path& data_dir) : ledger_(data_dir) {
  for (const std::string& d : ledger_.damage()) spdlog::error("change ledger damaged: {}", d);
  if (ledger_.torn_tail()) spdlog::info("{}: an answer torn by a power cut was ended", ledger_.path().string());
}

bool RequestLedger::kept(msg::Operation operation) {
  switch (operation) {
    case msg::BUILD:
    case msg::EXTEND:
    case msg::CANCEL:
    case msg::DROP:
    case msg::TASK_ADD:
    case msg::TASK_REMOVE:
      return true;
    default:
      return false;
  }
}

std::optional<msg::Reply> RequestLedger::from_before(const msg::ChangeRequest& request, msg::Reply reply) const {
  if (!kept(request.args()._d())) return std::nullopt;
  const auto entry = ledger_.from_before(request.client_id().to_string(), request.request_seq());
  if (!entry) return std::nullopt;
  if (entry->answer) {
    reply.ok(entry->answer->ok);
    reply.error(entry->answer->error);
    reply.message(entry->answer->message);
    return reply;
  }
  reply.ok(false);
  reply.error(
      fmt::format("request: kind: interrupted: daemon {} stopped while it was doing this {} of scene '{}' "
                  "(request #{}), before it answered; it may have been done: check `ispars stats {}` before "
                  "sending it again",
                  reply.server_id().to_string(), entry->operation, entry->scene, entry->seq, entry->scene));
  return reply;
}

void RequestLedger::begin(const msg::ChangeRequest& request) {
  ledger_.begin(request.client_id().to_string(), request.request_seq(), wire::to_string(request.args()._d()),
                request.scene().to_string());
}

void RequestLedger::answered(const msg::Reply& reply) {
  if (!kept(reply.body()._d())) return;
  ledger_.answer(reply.client_id().to_string(), reply.request_seq(),
                 service::LedgerAnswer{reply.ok(), reply.error(), reply.message()});
}

}  // namespace ispars::server
