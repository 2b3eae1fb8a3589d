#include "ispars/service/change_ledger.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <set>

#include "ispars/roadmap/record_file.hpp"
#include "ispars/roadmap/sealed_file.hpp"

namespace ispars::service {
namespace {

using json = nlohmann::json;

// `s` as valid UTF-8 (an invalid byte replaced), which a JSON record can hold: errors may quote a
// client's bytes.
std::string utf8(const std::string& s) {
  return json::parse(json(s).dump(-1, ' ', false, json::error_handler_t::replace)).get<std::string>();
}

std::string begun_line(const LedgerEntry& e) {
  return seal_json({{"begun", utf8(e.operation)}, {"client", utf8(e.client)}, {"seq", e.seq}, {"scene", utf8(e.scene)}})
             .dump() +
         "\n";
}

std::string answer_line(const std::string& client, std::uint64_t seq, const LedgerAnswer& a) {
  return seal_json({{"answered", a.ok},
                    {"client", utf8(client)},
                    {"seq", seq},
                    {"error", utf8(a.error)},
                    {"message", utf8(a.message)}})
             .dump() +
         "\n";
}

}  // namespace

ChangeLedger::ChangeLedger(const std::filesystem::path& data_dir, FileSystem& fs, std::size_t keep)
    : path_(data_dir / ".changes.log"), fs_(fs), keep_(keep) {
  const bool created = !fs_.exists(path_);
  file_ = fs_.open(path_, FileSystem::Open::existing_or_new);
  if (!file_) throw std::runtime_error(fmt::format("cannot open {}", path_.string()));
  if (created) fsync_directory_of(path_, fs_);
  read_existing();
  // A torn last line (a power cut in an unsynced answer) is ended, and marked as a tear, so the
  // next record starts a line and the next open does not take it for damage.
  if (torn_at_) {
    std::string mark(1, '\n');
    mark += seal_json({{"torn", *torn_at_}}).dump();
    mark += '\n';
    file_->append(mark);
    file_->sync();
  }
}

void ChangeLedger::read_existing() {
  const std::string text = file_->read(0, file_->size());
  std::map<Key, std::size_t> index;  // into recent_
  std::set<std::uint64_t> bad;       // offsets of records that fail their seal
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view line(text.data() + at, end - at);
    const std::size_t offset = at;
    at = end + 1;
    if (line.empty()) continue;
    ++records_;
    json j = json::parse(line, nullptr, false);
    const bool intact = !j.is_discarded() && j.is_object() && open_sealed_json(j) == Seal::intact;
    if (intact && j.contains("torn") && j.at("torn").is_number_unsigned()) {
      bad.erase(j.at("torn").get<std::uint64_t>());  // a tear ended at an earlier open: not damage
      continue;
    }
    if (!intact || !j.contains("client") || !j.contains("seq") || !j.at("seq").is_number_unsigned() ||
        !j.at("client").is_string()) {
      if (end == text.size()) {  // a last line never ended: an unsynced answer torn by a power cut
        torn_at_ = offset;
        continue;
      }
      bad.insert(offset);
      continue;
    }
    const Key key{j.at("client").get<std::string>(), j.at("seq").get<std::uint64_t>()};
    if (j.contains("begun")) {
      index[key] = recent_.size();
      recent_.push_back({key.first, key.second, j.at("begun").get<std::string>(), j.value("scene", ""), std::nullopt});
    } else if (const auto it = index.find(key); it != index.end() && j.contains("answered")) {
      recent_[it->second].answer =
          LedgerAnswer{j.at("answered").get<bool>(), j.value("error", ""), j.value("message", "")};
    }
  }
  for (const std::uint64_t offset : bad) {
    damage_.push_back(fmt::format("{}: the record at byte {} fails its checksum (skipped)", path_.string(), offset));
  }
  for (const LedgerEntry& e : recent_) before_[{e.client, e.seq}] = e;
  while (recent_.size() > keep_) recent_.pop_front();
}

std::optional<LedgerEntry> ChangeLedger::from_before(const std::string& client, std::uint64_t seq) const {
  std::lock_guard lock(mutex_);
  const auto it = before_.find({client, seq});
  if (it == before_.end()) return std::nullopt;
  return it->second;
}

void ChangeLedger::begin(const std::string& client, std::uint64_t seq, const std::string& operation,
                         const std::string& scene) {
  std::lock_guard lock(mutex_);
  LedgerEntry e{client, seq, operation, scene, std::nullopt};
  append(begun_line(e), true);
  recent_.push_back(std::move(e));
  if (recent_.size() > keep_) recent_.pop_front();
  if (records_ > 4 * keep_) compact();
}

void ChangeLedger::answer(const std::string& client, std::uint64_t seq, const LedgerAnswer& answer) {
  std::lock_guard lock(mutex_);
  const auto it = std::find_if(recent_.rbegin(), recent_.rend(),
                               [&](const LedgerEntry& e) { return e.client == client && e.seq == seq; });
  if (it == recent_.rend() || it->answer) return;  // not begun here, or answered already
  try {
    append(answer_line(client, seq, answer), false);
  } catch (const std::exception& e) {
    spdlog::error("the answer of {} #{} is not recorded in {}: {}", client, seq, path_.string(), e.what());
    return;
  }
  it->answer = answer;
}

void ChangeLedger::append(const std::string& line, bool sync) {
  file_->append(line);
  if (sync) file_->sync();
  ++records_;
}

void ChangeLedger::compact() {
  std::string text;
  for (const LedgerEntry& e : recent_) {
    text += begun_line(e);
    if (e.answer) text += answer_line(e.client, e.seq, *e.answer);
  }
  try {
    file_.reset();
    if (!damage_.empty() && !fs_.exists(aside_path())) {  // damaged records are kept where they can be read
      write_file_atomically(aside_path(), fs_.read(path_).value_or(""), fs_);
      spdlog::warn("{} had damaged records: kept as {} before it is rewritten", path_.string(), aside_path().string());
    }
    write_file_atomically(path_, text, fs_);
  } catch (const std::exception& e) {
    spdlog::error("rewriting {} failed: {}; it keeps growing", path_.string(), e.what());
  }
  file_ = fs_.open(path_, FileSystem::Open::existing_or_new);
  if (!file_) throw std::runtime_error(fmt::format("cannot open {} again after rewriting it", path_.string()));
  records_ = 0;
  for (const LedgerEntry& e : recent_) records_ += e.answer ? 2 : 1;
}

}  // namespace ispars::service
