#pragma once
// An MCAP file writer (https://mcap.dev/spec): schemas, channels and timestamped messages in
// chunks of about 1 MiB, each chunk followed by its message indexes, and a summary (schemas,
// channels, chunk indexes, statistics, summary offsets) that indexed readers such as Foxglove
// seek by. Uncompressed; CRC-32 on every chunk and on the data section. The file is written to a
// temporary beside the path and renamed into place by finish(): a reader never sees half a file.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace ispars::record {

class McapWriter {
 public:
  /// Opens the temporary file and writes the header; throws std::runtime_error naming the path.
  McapWriter(std::filesystem::path path, const std::string& library);
  /// Without finish(): the temporary is removed and nothing is left at the path.
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// A schema (`encoding` e.g. "jsonschema"); its id, from 1.
  std::uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  /// A channel on `topic` of `schema` (0: none) whose messages are `message_encoding` (e.g. "json").
  std::uint16_t add_channel(std::uint16_t schema, const std::string& topic, const std::string& message_encoding);
  /// One message, `log_time` in nanoseconds since the epoch (never earlier than the last).
  void write(std::uint16_t channel, std::uint64_t log_time, const std::string& data);
  /// Writes the last chunk, the summary and the footer, and renames the file into place.
  void finish();

  [[nodiscard]] std::uint64_t messages() const { return message_count_; }

 private:
  struct Chunk {
    std::string records;
    std::uint64_t start = 0, end = 0;
    std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> index;  // time, offset
  };
  struct ChunkIndex {
    std::uint64_t start = 0, end = 0, offset = 0, length = 0, index_length = 0, size = 0;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
  };
  void put(const std::string& record);  // to the file's data section
  void flush_chunk();
  [[nodiscard]] std::string summary(std::uint64_t summary_start, std::string& offsets) const;

  std::filesystem::path path_, temporary_;
  std::ofstream out_;
  std::uint64_t written_ = 0;
  std::uint32_t data_crc_ = 0;
  std::vector<std::string> schemas_, channels_;  // their records, for the summary
  Chunk chunk_;
  std::vector<ChunkIndex> chunks_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::map<std::uint16_t, std::uint32_t> sequences_;
  std::uint64_t message_count_ = 0, first_time_ = 0, last_time_ = 0;
  bool finished_ = false;
};

}  // namespace ispars::record
