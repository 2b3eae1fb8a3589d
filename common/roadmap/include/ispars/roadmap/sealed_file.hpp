#pragma once
// Seals for the small text files a store keeps beside its checked records (recipe.json, job
// records, drop marks, head): each carries a CRC-32 of its content, so a flipped bit is named
// instead of believed. A file written before seals existed has none and is read as before.

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace ispars {

/// What a file's seal says about its content.
enum class Seal { intact, absent, broken };

/// A sealed text file's content and its seal.
struct SealedText {
  std::string body;  ///< The text before the seal line (all of it when there is none).
  Seal seal = Seal::absent;
};

/// `body` (ending in a newline) and a last line "crc32 XXXXXXXX" over it.
[[nodiscard]] std::string seal_text(std::string_view body);

/// Splits off and checks the seal line; a last line that is not one leaves the seal absent.
[[nodiscard]] SealedText open_sealed_text(std::string_view text);

/// `j` (an object) with a "crc32" member: the CRC-32 of j's compact dump without it (keys sorted,
/// numbers in their shortest round-trip form, so re-indenting the file keeps the seal intact).
[[nodiscard]] nlohmann::json seal_json(nlohmann::json j);

/// Removes `j`'s "crc32" member and checks it against the rest.
[[nodiscard]] Seal open_sealed_json(nlohmann::json& j);

}  // namespace ispars
