#include "ispars/record/mcap_writer.hpp"

#include <zlib.h>

#include <stdexcept>
#include <system_error>

namespace ispars::record {
namespace {

constexpr char kMagic[] = "\x89MCAP0\r\n";
constexpr std::size_t kChunkBytes = 1 << 20;
enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

template <class T>
void put_int(std::string& b, T v) {  // little-endian, as MCAP is
  for (std::size_t i = 0; i < sizeof(T); ++i)
    b.push_back(static_cast<char>((static_cast<std::uint64_t>(v) >> (8 * i)) & 0xff));
}
void put_text(std::string& b, const std::string& s) {
  put_int<std::uint32_t>(b, static_cast<std::uint32_t>(s.size()));
  b += s;
}
std::string record(Op op, const std::string& content) {
  std::string r(1, static_cast<char>(op));
  put_int<std::uint64_t>(r, content.size());
  return r + content;
}
// A map<uint16, uint64> field: its byte length, then the pairs.
std::string id_map(const std::map<std::uint16_t, std::uint64_t>& m) {
  std::string b;
  put_int<std::uint32_t>(b, static_cast<std::uint32_t>(m.size() * 10));
  for (const auto& [k, v] : m) {
    put_int(b, k);
    put_int(b, v);
  }
  return b;
}
std::uint32_t crc_of(const std::string& bytes) {
  return static_cast<std::uint32_t>(
      ::crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
}

}  // namespace

McapWriter::McapWriter(std::filesystem::path path, const std::string& library)
    : path_(std::move(path)), temporary_(path_.string() + ".partial") {
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot write " + temporary_.string());
  out_.write(kMagic, 8);
  written_ = 8;
  std::string header;
  put_text(header, "");  // no profile: the messages are JSON with their schemas
  put_text(header, library);
  put(record(kHeader, header));
}

McapWriter::~McapWriter() {
  if (finished_) return;
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_, ignored);
}

void McapWriter::put(const std::string& bytes) {
  out_.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  written_ += bytes.size();
}

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, const std::string& data) {
  const auto id = static_cast<std::uint16_t>(schemas_.size() + 1);
  std::string b;
  put_int(b, id);
  put_text(b, name);
  put_text(b, encoding);
  put_text(b, data);
  schemas_.push_back(record(kSchema, b));
  put(schemas_.back());
  return id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema, const std::string& topic,
                                      const std::string& message_encoding) {
  const auto id = static_cast<std::uint16_t>(channels_.size() + 1);
  std::string b;
  put_int(b, id);
  put_int(b, schema);
  put_text(b, topic);
  put_text(b, message_encoding);
  put_int<std::uint32_t>(b, 0);  // no metadata
  channels_.push_back(record(kChannel, b));
  put(channels_.back());
  channel_counts_[id] = 0;
  return id;
}

void McapWriter::write(std::uint16_t channel, std::uint64_t log_time, const std::string& data) {
  if (message_count_ == 0) first_time_ = log_time;
  last_time_ = std::max(last_time_, log_time);
  if (chunk_.records.empty()) chunk_.start = log_time;
  chunk_.end = std::max(chunk_.end, log_time);
  std::string b;
  put_int(b, channel);
  put_int<std::uint32_t>(b, sequences_[channel]++);
  put_int(b, log_time);
  put_int(b, log_time);  // published when logged
  chunk_.index[channel].emplace_back(log_time, chunk_.records.size());
  chunk_.records += record(kMessage, b + data);
  ++channel_counts_[channel];
  ++message_count_;
  if (chunk_.records.size() >= kChunkBytes) flush_chunk();
}

void McapWriter::flush_chunk() {
  if (chunk_.records.empty()) return;
  ChunkIndex ci;
  ci.start = chunk_.start;
  ci.end = chunk_.end;
  ci.offset = written_;
  ci.size = chunk_.records.size();
  std::string b;
  put_int(b, chunk_.start);
  put_int(b, chunk_.end);
  put_int<std::uint64_t>(b, chunk_.records.size());
  put_int(b, crc_of(chunk_.records));
  put_text(b, "");  // no compression
  put_int<std::uint64_t>(b, chunk_.records.size());
  b += chunk_.records;
  const std::string chunk = record(kChunk, b);
  ci.length = chunk.size();
  put(chunk);
  const std::uint64_t indexes_at = written_;
  for (const auto& [channel, entries] : chunk_.index) {
    std::string m;
    put_int(m, channel);
    put_int<std::uint32_t>(m, static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [time, offset] : entries) {
      put_int(m, time);
      put_int(m, offset);
    }
    ci.index_offsets[channel] = written_;
    put(record(kMessageIndex, m));
  }
  ci.index_length = written_ - indexes_at;
  chunks_.push_back(std::move(ci));
  chunk_ = Chunk{};
}

std::string McapWriter::summary(std::uint64_t summary_start, std::string& offsets) const {
  std::string out;
  const auto group = [&](Op op, const std::string& records) {
    if (records.empty()) return;
    std::string so(1, static_cast<char>(op));
    put_int<std::uint64_t>(so, summary_start + out.size());
    put_int<std::uint64_t>(so, records.size());
    offsets += record(kSummaryOffset, so);
    out += records;
  };
  std::string schemas, channels, indexes, stats;
  for (const std::string& s : schemas_) schemas += s;
  for (const std::string& c : channels_) channels += c;
  for (const ChunkIndex& ci : chunks_) {
    std::string b;
    put_int(b, ci.start);
    put_int(b, ci.end);
    put_int(b, ci.offset);
    put_int(b, ci.length);
    b += id_map(ci.index_offsets);
    put_int(b, ci.index_length);
    put_text(b, "");
    put_int(b, ci.size);  // compressed: as uncompressed
    put_int(b, ci.size);
    indexes += record(kChunkIndex, b);
  }
  put_int<std::uint64_t>(stats, message_count_);
  put_int<std::uint16_t>(stats, static_cast<std::uint16_t>(schemas_.size()));
  put_int<std::uint32_t>(stats, static_cast<std::uint32_t>(channels_.size()));
  put_int<std::uint32_t>(stats, 0);  // attachments
  put_int<std::uint32_t>(stats, 0);  // metadata
  put_int<std::uint32_t>(stats, static_cast<std::uint32_t>(chunks_.size()));
  put_int(stats, first_time_);
  put_int(stats, last_time_);
  stats += id_map(channel_counts_);
  group(kSchema, schemas);
  group(kChannel, channels);
  group(kChunkIndex, indexes);
  group(kStatistics, record(kStatistics, stats));
  return out;
}

void McapWriter::finish() {
  if (finished_) return;
  flush_chunk();
  std::string data_end;
  put_int<std::uint32_t>(data_end, 0);  // the data section's CRC: not computed
  put(record(kDataEnd, data_end));
  const std::uint64_t summary_start = written_;
  std::string offsets;
  put(summary(summary_start, offsets));
  const std::uint64_t offsets_start = written_;
  put(offsets);
  std::string footer;
  put_int(footer, summary_start);
  put_int(footer, offsets_start);
  put_int<std::uint32_t>(footer, 0);  // the summary's CRC: not computed
  put(record(kFooter, footer));
  out_.write(kMagic, 8);
  out_.flush();
  out_.close();
  if (!out_) throw std::runtime_error("cannot write " + temporary_.string());
  std::filesystem::rename(temporary_, path_);
  finished_ = true;
}

}  // namespace ispars::record
