// Record files: checksummed appends, torn tails, atomic whole-file writes.

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/resource.h>

#include <fstream>

#include "ispars/roadmap/record_file.hpp"
#include "support/test_support.hpp"

namespace ispars {
namespace {

const auto accept_all = [](const std::string&) { return std::string(); };

TEST(RecordFile, Crc32MatchesTheStandardCheckValue) {
  EXPECT_EQ(crc32("123456789", 9), 0xCBF43926u);
  EXPECT_EQ(crc32("", 0), 0u);
}

TEST(RecordFile, EveryPrefixOfTheFileReadsAsTheWholeRecordsItHolds) {
  test::TempDir dir;
  const auto path = dir.path() / "r.log";
  const std::vector<std::string> payloads = {"alpha", "", std::string(1000, 'x'), "omega"};
  {
    RecordFileWriter writer(path, "MAGIC001", 0);
    for (const auto& p : payloads) writer.append(p);
  }
  const std::string full = test::read_text(path);
  std::vector<std::size_t> ends = {8};
  for (const auto& p : payloads) ends.push_back(ends.back() + 8 + p.size());
  ASSERT_EQ(ends.back(), full.size());
  for (std::size_t cut = 0; cut <= full.size(); ++cut) {
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(full.data(), static_cast<std::streamsize>(cut));
    const RecordReplay replay = read_record_file(path, "MAGIC001", accept_all);
    std::size_t whole = 0;
    while (whole < payloads.size() && ends[whole + 1] <= cut) ++whole;
    ASSERT_EQ(replay.payloads.size(), whole) << "cut at " << cut;
    for (std::size_t i = 0; i < whole; ++i) EXPECT_EQ(replay.payloads[i], payloads[i]);
    EXPECT_EQ(replay.torn_tail, cut != 0 && cut != ends[whole]) << "cut at " << cut;
    // Reopening cuts the tail and appends cleanly after the whole records.
    {
      RecordFileWriter writer(path, "MAGIC001", replay.valid_bytes);
      writer.append("after");
    }
    const RecordReplay again = read_record_file(path, "MAGIC001", accept_all);
    ASSERT_EQ(again.payloads.size(), whole + 1);
    EXPECT_EQ(again.payloads.back(), "after");
    EXPECT_FALSE(again.torn_tail);
  }
}

TEST(RecordFile, AFlippedByteOrARejectedRecordEndsTheValidPrefix) {
  test::TempDir dir;
  const auto path = dir.path() / "r.log";
  {
    RecordFileWriter writer(path, "MAGIC001", 0);
    writer.append("one");
    writer.append("two");
    writer.append("three");
  }
  std::string bytes = test::read_text(path);
  bytes[8 + 8 + 3 + 8 + 1] ^= 0x40;  // inside "two"
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  RecordReplay replay = read_record_file(path, "MAGIC001", accept_all);
  ASSERT_EQ(replay.payloads.size(), 1u);
  EXPECT_EQ(replay.tail_problem, "record checksum mismatch");

  bytes[8 + 8 + 3 + 8 + 1] ^= 0x40;
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  replay = read_record_file(path, "MAGIC001", [](const std::string& p) {
    return p == "three" ? std::string("three is refused") : std::string();
  });
  EXPECT_EQ(replay.payloads.size(), 2u);
  EXPECT_EQ(replay.tail_problem, "three is refused");
  EXPECT_TRUE(replay.torn_tail);
}

// Only an incomplete last record is what a crash while appending leaves. A record that fails its
// checksum with more bytes after it, or an intact record the check refuses, is damage.
TEST(RecordFile, OnlyAnIncompleteLastRecordIsATornTailAnythingElseIsDamage) {
  test::TempDir dir;
  const auto path = dir.path() / "r.log";
  const std::vector<std::string> payloads = {"one", "two", "three", "four", "five"};
  {
    RecordFileWriter writer(path, "MAGIC001", 0);
    for (const auto& p : payloads) writer.append(p);
  }
  const std::string bytes = test::read_text(path);
  std::vector<std::size_t> starts;  // where each record's header begins
  for (std::size_t at = 8, i = 0; i < payloads.size(); at += 8 + payloads[i].size(), ++i) starts.push_back(at);
  const auto read_with = [&](const std::string& content, const RecordCheck& check) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << content;
    return read_record_file(path, "MAGIC001", check);
  };
  for (std::size_t r = 0; r < payloads.size(); ++r) {  // a flipped payload byte in each record
    std::string flipped = bytes;
    flipped[starts[r] + 8] ^= 0x01;
    const RecordReplay replay = read_with(flipped, accept_all);
    EXPECT_EQ(replay.payloads.size(), r);
    EXPECT_EQ(replay.valid_bytes, starts[r]);
    EXPECT_EQ(replay.damaged, r + 1 < payloads.size()) << "record " << r;
  }
  for (std::size_t cut = starts.back() + 1; cut < bytes.size(); ++cut) {  // the last record cut short
    const RecordReplay replay = read_with(bytes.substr(0, cut), accept_all);
    EXPECT_TRUE(replay.torn_tail);
    EXPECT_FALSE(replay.damaged) << "cut at " << cut;
  }
  const RecordReplay refused = read_with(bytes, [](const std::string& p) {
    return p == "five" ? std::string("five is refused") : std::string();
  });
  EXPECT_TRUE(refused.damaged) << "an intact record the check refuses is not a torn write";
  EXPECT_EQ(refused.payloads.size(), 4u);
  EXPECT_FALSE(read_with(bytes, accept_all).damaged);
}

TEST(RecordFile, AnotherMagicIsAnErrorAndAMissingFileIsEmpty) {
  test::TempDir dir;
  EXPECT_TRUE(read_record_file(dir.path() / "none", "MAGIC001", accept_all).payloads.empty());
  const auto path = dir.write("other", "SOMETHING ELSE ENTIRELY");
  EXPECT_THROW((void)read_record_file(path, "MAGIC001", accept_all), std::runtime_error);
}

TEST(RecordFile, AtomicWritesReplaceTheWholeFileAndLeaveNoTemporary) {
  test::TempDir dir;
  const auto path = dir.path() / "f.json";
  write_file_atomically(path, "first");
  write_file_atomically(path, "second, longer");
  EXPECT_EQ(test::read_text(path), "second, longer");
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "f.json.tmp"));
  EXPECT_THROW(write_file_atomically(dir.path() / "missing-dir" / "f", "x"), std::runtime_error);
}

// A write that fails partway (a full disk; here the file size limit, which fails a write the same
// way with EFBIG) leaves no partial record behind: the next append, once there is room, follows
// the last whole record, and the file reads back whole with no torn tail.
TEST(RecordFile, AFailedAppendIsCutBackSoTheNextRecordFollowsAWholeOne) {
  test::TempDir dir;
  const auto path = dir.path() / "journal";
  {
    RecordFileWriter writer(path, "MAGIC001", 0);
    writer.append("first record");
    const auto whole = std::filesystem::file_size(path);
    ASSERT_EQ(writer.size(), whole);
    struct sigaction ignore{}, previous{};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGXFSZ, &ignore, &previous);
    rlimit old{};
    ::getrlimit(RLIMIT_FSIZE, &old);
    rlimit small = old;
    small.rlim_cur = whole + 10;  // room for part of the next record only
    ::setrlimit(RLIMIT_FSIZE, &small);
    EXPECT_THROW(writer.append(std::string(1000, 'x')), std::runtime_error);
    ::setrlimit(RLIMIT_FSIZE, &old);
    ::sigaction(SIGXFSZ, &previous, nullptr);
    EXPECT_EQ(std::filesystem::file_size(path), whole) << "the partial record stayed";
    writer.append("second record");
  }
  const RecordReplay replay = read_record_file(path, "MAGIC001", accept_all);
  EXPECT_FALSE(replay.torn_tail);
  EXPECT_FALSE(replay.damaged);
  EXPECT_EQ(replay.payloads, (std::vector<std::string>{"first record", "second record"}));
}

// No record size is a wall: a payload of 4 GiB or more gets a 64-bit length after an escape.
// (A real 4 GiB record would take seconds of disk here; the escape is what differs, so a small
// record written in the long form stands in for it.)
TEST(RecordFile, ALongLengthAfterTheEscapeReadsInTheCurrentFormatOnly) {
  EXPECT_EQ(record_header(5, 0).size(), 8u);
  EXPECT_EQ(record_header(kLegacyRecordLimit, 0).size(), 8u);
  const std::string big = record_header(std::uint64_t{5} << 30, 0x1234);
  ASSERT_EQ(big.size(), 16u);
  EXPECT_EQ(big.substr(0, 4), std::string(4, '\xff'));
  ByteReader in(std::string_view(big).substr(8));
  EXPECT_EQ(in.get<std::uint64_t>(), std::uint64_t{5} << 30);

  test::TempDir dir;
  const auto path = dir.path() / "r.log";
  const RecordFormat format{"MAGIC002", "MAGIC001"};
  std::string payload = "hello";
  std::string record;
  put_bytes(record, std::uint32_t{0xFFFFFFFFu});
  put_bytes(record, crc32(payload.data(), payload.size()));
  put_bytes(record, std::uint64_t{payload.size()});
  record += payload;
  std::ofstream(path, std::ios::binary) << "MAGIC002" << record;
  RecordReplay replay = read_record_file(path, format, accept_all);
  EXPECT_EQ(replay.payloads, std::vector<std::string>{"hello"});
  EXPECT_FALSE(replay.torn_tail);
  EXPECT_FALSE(replay.legacy);
  // In a legacy file the same bytes are a 32-bit length running past the end: never read as one.
  std::ofstream(path, std::ios::binary | std::ios::trunc) << "MAGIC001" << record;
  replay = read_record_file(path, format, accept_all);
  EXPECT_TRUE(replay.legacy);
  EXPECT_TRUE(replay.payloads.empty());
  EXPECT_TRUE(replay.torn_tail);
  // Torn inside the long header: a torn tail, not damage.
  std::ofstream(path, std::ios::binary | std::ios::trunc) << "MAGIC002" << record.substr(0, 12);
  replay = read_record_file(path, format, accept_all);
  EXPECT_TRUE(replay.torn_tail);
  EXPECT_FALSE(replay.damaged);
  // Neither magic: refused by name.
  std::ofstream(path, std::ios::binary | std::ios::trunc) << "MAGIC003" << record;
  EXPECT_THROW((void)read_record_file(path, format, accept_all), std::runtime_error);
}

TEST(RecordFile, ALegacyFileKeepsItsMagicAndRefusesARecordOver4GiBByName) {
  test::TempDir dir;
  const auto path = dir.path() / "r.log";
  const RecordFormat format{"MAGIC002", "MAGIC001"};
  {
    RecordFileWriter writer(path, "MAGIC001", 0);
    writer.append("old");
  }
  RecordReplay replay = read_record_file(path, format, accept_all);
  ASSERT_TRUE(replay.legacy);
  RecordFileWriter writer(path, format, replay.valid_bytes);
  writer.append("appended");
  // The size is checked before a byte is read, so this view is never dereferenced.
  const std::string_view huge("x", 1);
  try {
    writer.append(std::string_view(huge.data(), std::size_t{5} << 30));
    FAIL() << "a 5 GiB record went into a legacy file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds the 4 GiB record limit of " + path.string()), std::string::npos)
        << e.what();
  }
  replay = read_record_file(path, format, accept_all);
  EXPECT_TRUE(replay.legacy);
  EXPECT_EQ(replay.payloads, (std::vector<std::string>{"old", "appended"}));
  EXPECT_FALSE(replay.torn_tail);
}

TEST(RecordFile, AnAtomicRecordFileStoppedMidwayLeavesTheOldFileAndNoTemporary) {
  test::TempDir dir;
  const auto path = dir.path() / "snapshot";
  write_record_file_atomically(path, "MAGIC002", "first");
  const std::string first = test::read_text(path);
  const std::string big(std::size_t{130} << 20, 'y');  // three pieces of 64 MiB
  int asked = 0;
  EXPECT_THROW(write_record_file_atomically(path, "MAGIC002", big, [&] { return ++asked < 2; }), RecordWriteStopped);
  EXPECT_EQ(asked, 2);
  EXPECT_EQ(test::read_text(path), first);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "snapshot.tmp"));
  write_record_file_atomically(path, "MAGIC002", big, [&] { return true; });
  const RecordReplay replay = read_record_file(path, "MAGIC002", accept_all);
  ASSERT_EQ(replay.payloads.size(), 1u);
  EXPECT_EQ(replay.payloads[0].size(), big.size());
}

TEST(RecordFile, ByteReaderRefusesToReadPastTheEnd) {
  std::string data;
  put_bytes(data, std::uint32_t{7});
  ByteReader in(data);
  EXPECT_EQ(in.get<std::uint32_t>(), 7u);
  EXPECT_TRUE(in.done());
  EXPECT_THROW((void)in.get<std::uint8_t>(), std::runtime_error);
  EXPECT_THROW((void)in.bytes(1), std::runtime_error);
}

}  // namespace
}  // namespace ispars
