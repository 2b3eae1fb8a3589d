#include "ispars/roadmap/sealed_file.hpp"

#include <fmt/format.h>

#include "ispars/roadmap/record_file.hpp"

namespace ispars {
namespace {

constexpr std::string_view kSealWord = "crc32 ";
constexpr std::size_t kSealLine = 6 + 8 + 1;  // "crc32 " + 8 hex digits + '\n'

std::string crc_text(std::string_view bytes) { return fmt::format("{:08x}", crc32(bytes.data(), bytes.size())); }

}  // namespace

std::string seal_text(std::string_view body) { return fmt::format("{}{}{}\n", body, kSealWord, crc_text(body)); }

SealedText open_sealed_text(std::string_view text) {
  SealedText out{std::string(text), Seal::absent};
  if (text.size() < kSealLine || !text.ends_with('\n')) return out;
  const std::string_view line = text.substr(text.size() - kSealLine);
  const std::size_t line_start = text.size() - kSealLine;
  if (!line.starts_with(kSealWord) || (line_start > 0 && text[line_start - 1] != '\n')) return out;
  const std::string_view body = text.substr(0, line_start);
  out.body = std::string(body);
  out.seal = line.substr(kSealWord.size(), 8) == crc_text(body) ? Seal::intact : Seal::broken;
  return out;
}

nlohmann::json seal_json(nlohmann::json j) {
  j.erase("crc32");
  const std::string crc = crc_text(j.dump());
  j["crc32"] = crc;
  return j;
}

Seal open_sealed_json(nlohmann::json& j) {
  if (!j.is_object() || !j.contains("crc32")) return Seal::absent;
  const nlohmann::json seal = j.at("crc32");
  j.erase("crc32");
  return seal.is_string() && seal.get<std::string>() == crc_text(j.dump()) ? Seal::intact : Seal::broken;
}

}  // namespace ispars
