// Seals (sealed_file.hpp): every single-bit flip of a sealed text or JSON file is caught; a file
// without a seal reads as before; re-indenting sealed JSON keeps the seal intact.

#include <gtest/gtest.h>

#include "ispars/roadmap/sealed_file.hpp"

namespace ispars {
namespace {

TEST(SealedFile, EveryBitFlipOfASealedTextIsCaught) {
  const std::string body = "1795904554570848036 3000 48213\n";
  const std::string sealed = seal_text(body);
  const SealedText intact = open_sealed_text(sealed);
  EXPECT_EQ(intact.seal, Seal::intact);
  EXPECT_EQ(intact.body, body);
  for (std::size_t bit = 0; bit < 8 * sealed.size(); ++bit) {
    std::string flipped = sealed;
    flipped[bit / 8] = static_cast<char>(flipped[bit / 8] ^ (1 << (bit % 8)));
    EXPECT_NE(open_sealed_text(flipped).seal, Seal::intact) << "bit " << bit;
  }
  const SealedText old = open_sealed_text(body);  // written before seals
  EXPECT_EQ(old.seal, Seal::absent);
  EXPECT_EQ(old.body, body);
  EXPECT_EQ(open_sealed_text("").seal, Seal::absent);
}

TEST(SealedFile, SealedJsonCatchesChangedValuesNotIndentation) {
  nlohmann::json j = {{"seed", 3}, {"scene", "s0"}, {"stretch", 1.05}, {"overrides", {{"p", 0.1}}}};
  const nlohmann::json sealed = seal_json(j);
  nlohmann::json read = nlohmann::json::parse(sealed.dump(2));
  EXPECT_EQ(open_sealed_json(read), Seal::intact);
  EXPECT_EQ(read, j) << "the seal member is removed";
  read = nlohmann::json::parse(sealed.dump());
  EXPECT_EQ(open_sealed_json(read), Seal::intact) << "indentation changed the seal";
  for (const auto& [key, value] : j.items()) {
    nlohmann::json changed = sealed;
    changed[key] = value.is_number_integer() ? nlohmann::json(2) : nlohmann::json("x");
    EXPECT_EQ(open_sealed_json(changed), Seal::broken) << key;
  }
  nlohmann::json resealed = seal_json(sealed);  // sealing again replaces the seal
  EXPECT_EQ(open_sealed_json(resealed), Seal::intact);
  nlohmann::json unsealed = j;
  EXPECT_EQ(open_sealed_json(unsealed), Seal::absent);
  nlohmann::json not_text = sealed;
  not_text["crc32"] = 7;
  EXPECT_EQ(open_sealed_json(not_text), Seal::broken);
}

}  // namespace
}  // namespace ispars
