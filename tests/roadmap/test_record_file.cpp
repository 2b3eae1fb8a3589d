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

// While it lives, a write past `bytes` in any file fails with EFBIG (as on a full disk), SIGXFSZ
// ignored.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGXFSZ, &ignore, &previous_);
    ::getrlimit(RLIMIT_FSIZE, &old_);
    rlimit small = old_;
    small.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &small);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &old_);
    ::sigaction(SIGXFSZ, &previous_, nullptr);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  struct sigaction previous_ {};
  rlimit old_{};
};

TEST(RecordFile, Crc32MatchesTheStandardCheckValue) {
  EXPECT_EQ(crc32("123456789", 9), 0xCBF43926u);
  EXPECT_EQ(crc32("", 0), 0u);
}

// The three layouts, each as the only magic of a format: every test of torn tails runs on each.
struct Layout {
  RecordLayout layout;
  std::size_t header;  // bytes per record header (records under 4 GiB)
  const char* magic;
};
constexpr Layout kLayouts[] = {{RecordLayout::checked, 16, "MAGIC003"},
                               {RecordLayout::escaped, 8, "MAGIC002"},
                               {RecordLayout::plain, 8, "MAGIC001"}};
RecordFormat format_of(const Layout& l) { return RecordFormat{{l.magic, l.layout}}; }

std::string layout_name(const Layout& l) { return l.magic; }

// Writes `payloads` as a new file in layout `l`; returns where each record's header begins.
std::vector<std::size_t> write_records(const std::filesystem::path& path, const Layout& l,
                                       const std::vector<std::string>& payloads) {
  std::filesystem::remove(path);
  RecordFileWriter writer(path, format_of(l), 0);
  std::vector<std::size_t> starts;
  for (const auto& p : payloads) {
    starts.push_back(writer.size());
    writer.append(p);
  }
  return starts;
}

void write_bytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(RecordFile, EveryPrefixOfTheFileReadsAsTheWholeRecordsItHolds) {
  for (const Layout& l : kLayouts) {
    SCOPED_TRACE(layout_name(l));
    test::TempDir dir;
    const auto path = dir.path() / "r.log";
    const std::vector<std::string> payloads = {"alpha", "", std::string(1000, 'x'), "omega"};
    (void)write_records(path, l, payloads);
    const std::string full = test::read_text(path);
    std::vector<std::size_t> ends = {8};
    for (const auto& p : payloads) ends.push_back(ends.back() + l.header + p.size());
    ASSERT_EQ(ends.back(), full.size());
    for (std::size_t cut = 0; cut <= full.size(); ++cut) {
      write_bytes(path, full.substr(0, cut));
      const RecordReplay replay = read_record_file(path, format_of(l), accept_all);
      std::size_t whole = 0;
      while (whole < payloads.size() && ends[whole + 1] <= cut) ++whole;
      ASSERT_EQ(replay.payloads.size(), whole) << "cut at " << cut;
      for (std::size_t i = 0; i < whole; ++i) EXPECT_EQ(replay.payloads[i], payloads[i]);
      EXPECT_EQ(replay.torn_tail, cut != 0 && cut != ends[whole]) << "cut at " << cut;
      EXPECT_FALSE(replay.damaged) << "cut at " << cut;
      // Reopening keeps the cut bytes aside, cuts them, and appends cleanly after the whole records.
      std::filesystem::path aside;
      {
        RecordFileWriter writer(path, format_of(l), replay.valid_bytes);
        aside = writer.set_aside();
        writer.append("after");
      }
      const std::size_t kept = replay.valid_bytes < 8 ? 0 : replay.valid_bytes;
      if (cut > kept) {
        ASSERT_FALSE(aside.empty()) << "cut at " << cut;
        EXPECT_EQ(test::read_text(aside), full.substr(kept, cut - kept)) << "cut at " << cut;
        std::filesystem::remove(aside);
      } else {
        EXPECT_TRUE(aside.empty()) << "cut at " << cut;
      }
      const RecordReplay again = read_record_file(path, format_of(l), accept_all);
      ASSERT_EQ(again.payloads.size(), whole + 1);
      EXPECT_EQ(again.payloads.back(), "after");
      EXPECT_FALSE(again.torn_tail);
    }
  }
}

TEST(RecordFile, AFlippedByteOrARejectedRecordEndsTheValidPrefix) {
  for (const Layout& l : kLayouts) {
    SCOPED_TRACE(layout_name(l));
    test::TempDir dir;
    const auto path = dir.path() / "r.log";
    const auto starts = write_records(path, l, {"one", "two", "three"});
    std::string bytes = test::read_text(path);
    bytes[starts[1] + l.header + 1] ^= 0x40;  // inside "two"
    write_bytes(path, bytes);
    RecordReplay replay = read_record_file(path, format_of(l), accept_all);
    ASSERT_EQ(replay.payloads.size(), 1u);
    EXPECT_EQ(replay.tail_problem, "record checksum mismatch");
    EXPECT_TRUE(replay.damaged);

    bytes[starts[1] + l.header + 1] ^= 0x40;
    write_bytes(path, bytes);
    replay = read_record_file(path, format_of(l), [](const std::string& p) {
      return p == "three" ? std::string("three is refused") : std::string();
    });
    EXPECT_EQ(replay.payloads.size(), 2u);
    EXPECT_EQ(replay.tail_problem, "three is refused");
    EXPECT_TRUE(replay.torn_tail);
    EXPECT_TRUE(replay.damaged);
  }
}

// Only an incomplete last record is what a crash while appending leaves. A record that fails its
// checksum with more bytes after it, or an intact record the check refuses, is damage.
TEST(RecordFile, OnlyAnIncompleteLastRecordIsATornTailAnythingElseIsDamage) {
  for (const Layout& l : kLayouts) {
    SCOPED_TRACE(layout_name(l));
    test::TempDir dir;
    const auto path = dir.path() / "r.log";
    const std::vector<std::string> payloads = {"one", "two", "three", "four", "five"};
    const auto starts = write_records(path, l, payloads);
    const std::string bytes = test::read_text(path);
    const auto read_with = [&](const std::string& content, const RecordCheck& check) {
      write_bytes(path, content);
      return read_record_file(path, format_of(l), check);
    };
    for (std::size_t r = 0; r < payloads.size(); ++r) {  // a flipped payload byte in each record
      std::string flipped = bytes;
      flipped[starts[r] + l.header] ^= 0x01;
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
    const RecordReplay refused = read_with(
        bytes, [](const std::string& p) { return p == "five" ? std::string("five is refused") : std::string(); });
    EXPECT_TRUE(refused.damaged) << "an intact record the check refuses is not a torn write";
    EXPECT_EQ(refused.payloads.size(), 4u);
    EXPECT_FALSE(read_with(bytes, accept_all).damaged);
  }
}

// In format 03 a record header is checked on its own: any flipped bit of a middle record's header
// (its length above all, which would otherwise send the reader past the end of the file) is
// damage, because valid records follow it. The same flip in the last record is a torn tail.
TEST(RecordFile, EveryFlippedBitOfAMiddleRecordsHeaderIsDamageInFormat03) {
  const Layout& l = kLayouts[0];
  test::TempDir dir;
  const auto path = dir.path() / "r.log";
  const std::vector<std::string> payloads = {"one", std::string(300, 'b'), "three", "four"};
  const auto starts = write_records(path, l, payloads);
  const std::string bytes = test::read_text(path);
  for (std::size_t r : {std::size_t{1}, payloads.size() - 1}) {
    const bool middle = r + 1 < payloads.size();
    for (std::size_t bit = 0; bit < 8 * l.header; ++bit) {
      std::string flipped = bytes;
      flipped[starts[r] + bit / 8] ^= static_cast<char>(1u << (bit % 8));
      write_bytes(path, flipped);
      const RecordReplay replay = read_record_file(path, format_of(l), accept_all);
      EXPECT_EQ(replay.payloads.size(), r) << "record " << r << " bit " << bit;
      EXPECT_EQ(replay.valid_bytes, starts[r]);
      EXPECT_EQ(replay.damaged, middle) << "record " << r << " bit " << bit;
      EXPECT_EQ(replay.tail_problem, "record header checksum mismatch") << "record " << r << " bit " << bit;
    }
  }
}

// Formats 01 and 02 have no header checksum: a middle record's length flipped to run past the end
// reads as a torn tail there. Nothing is lost even then: the writer keeps every cut byte aside.
TEST(RecordFile, AnOlderFormatsFlippedLengthIsCutOnlyAfterItsBytesAreKeptAside) {
  for (const Layout& l : {kLayouts[1], kLayouts[2]}) {
    SCOPED_TRACE(layout_name(l));
    test::TempDir dir;
    const auto path = dir.path() / "r.log";
    const auto starts = write_records(path, l, {"one", "two", "three"});
    std::string bytes = test::read_text(path);
    bytes[starts[1] + 3] ^= 0x40;  // the length's top byte: past the end
    write_bytes(path, bytes);
    const RecordReplay replay = read_record_file(path, format_of(l), accept_all);
    ASSERT_EQ(replay.payloads.size(), 1u);
    EXPECT_EQ(replay.tail_problem, "record runs past the end of the file");
    RecordFileWriter writer(path, format_of(l), replay.valid_bytes);
    EXPECT_EQ(writer.set_aside(), dir.path() / "r.log.torn.1");
    EXPECT_EQ(test::read_text(writer.set_aside()), bytes.substr(starts[1]));
    EXPECT_EQ(test::read_text(path), bytes.substr(0, starts[1]));
  }
}

// The copy aside comes first: when it cannot be made, the writer throws and cuts nothing. Later
// cuts of the same file get their own numbers.
TEST(RecordFile, ATailThatCannotBeKeptAsideIsNotCut) {
  test::TempDir dir;
  const auto path = dir.path() / "r.log";
  (void)write_records(path, kLayouts[0], {"one", std::string(5000, 't')});
  const std::string bytes = test::read_text(path);
  const std::string torn = bytes.substr(0, bytes.size() - 10);
  write_bytes(path, torn);
  const RecordReplay replay = read_record_file(path, "MAGIC003", accept_all);
  ASSERT_TRUE(replay.torn_tail);
  ASSERT_FALSE(replay.damaged);
  {
    const FileSizeLimit limit(100);  // the copy of the 5,000-byte tail cannot be written
    EXPECT_THROW(RecordFileWriter(path, "MAGIC003", replay.valid_bytes), std::runtime_error);
  }
  EXPECT_EQ(test::read_text(path), torn) << "the tail was cut without a copy";
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "r.log.torn.1")) << "a partial copy stayed";
  {
    RecordFileWriter writer(path, "MAGIC003", replay.valid_bytes);
    EXPECT_EQ(writer.set_aside(), dir.path() / "r.log.torn.1");
    writer.append("x");
  }
  write_bytes(path, test::read_text(path) + "junk");
  RecordFileWriter writer(path, "MAGIC003", read_record_file(path, "MAGIC003", accept_all).valid_bytes);
  EXPECT_EQ(writer.set_aside(), dir.path() / "r.log.torn.2");
  EXPECT_EQ(test::read_text(writer.set_aside()), "junk");
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
    {
      const FileSizeLimit limit(whole + 10);  // room for part of the next record only
      EXPECT_THROW(writer.append(std::string(1000, 'x')), std::runtime_error);
    }
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
TEST(RecordFile, ALongLengthAfterTheEscapeReadsInFormat02Only) {
  EXPECT_EQ(record_header(5, 0).size(), 16u);
  EXPECT_EQ(record_header(std::uint64_t{5} << 30, 0).size(), 16u);
  EXPECT_EQ(record_header(5, 0, RecordLayout::escaped).size(), 8u);
  EXPECT_EQ(record_header(kLegacyRecordLimit, 0, RecordLayout::escaped).size(), 8u);
  const std::string big = record_header(std::uint64_t{5} << 30, 0x1234, RecordLayout::escaped);
  ASSERT_EQ(big.size(), 16u);
  EXPECT_EQ(big.substr(0, 4), std::string(4, '\xff'));
  ByteReader in(std::string_view(big).substr(8));
  EXPECT_EQ(in.get<std::uint64_t>(), std::uint64_t{5} << 30);

  test::TempDir dir;
  const auto path = dir.path() / "r.log";
  const RecordFormat format{{"MAGIC002", RecordLayout::escaped}, {"MAGIC001", RecordLayout::plain}};
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
  EXPECT_EQ(replay.layout, RecordLayout::escaped);
  // In a format 01 file the same bytes are a 32-bit length running past the end: never read as one.
  std::ofstream(path, std::ios::binary | std::ios::trunc) << "MAGIC001" << record;
  replay = read_record_file(path, format, accept_all);
  EXPECT_EQ(replay.layout, RecordLayout::plain);
  EXPECT_TRUE(replay.payloads.empty());
  EXPECT_TRUE(replay.torn_tail);
  // Torn inside the long header: a torn tail, not damage.
  std::ofstream(path, std::ios::binary | std::ios::trunc) << "MAGIC002" << record.substr(0, 12);
  replay = read_record_file(path, format, accept_all);
  EXPECT_TRUE(replay.torn_tail);
  EXPECT_FALSE(replay.damaged);
  // Neither magic: refused by name.
  std::ofstream(path, std::ios::binary | std::ios::trunc) << "MAGIC004" << record;
  EXPECT_THROW((void)read_record_file(path, format, accept_all), std::runtime_error);
}

TEST(RecordFile, AnOlderFileKeepsItsMagicAndLayoutAndFormat01RefusesARecordOver4GiBByName) {
  test::TempDir dir;
  const auto path = dir.path() / "r.log";
  const RecordFormat format{
      {"MAGIC003", RecordLayout::checked}, {"MAGIC002", RecordLayout::escaped}, {"MAGIC001", RecordLayout::plain}};
  {
    RecordFileWriter writer(path, RecordFormat{{"MAGIC001", RecordLayout::plain}}, 0);
    writer.append("old");
  }
  RecordReplay replay = read_record_file(path, format, accept_all);
  ASSERT_EQ(replay.layout, RecordLayout::plain);
  RecordFileWriter writer(path, format, replay.valid_bytes);
  writer.append("appended");
  // The size is checked before a byte is read, so this view is never dereferenced.
  const std::string_view huge("x", 1);
  try {
    writer.append(std::string_view(huge.data(), std::size_t{5} << 30));
    FAIL() << "a 5 GiB record went into a format 01 file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds the 4 GiB record limit of " + path.string()), std::string::npos)
        << e.what();
  }
  replay = read_record_file(path, format, accept_all);
  EXPECT_EQ(replay.layout, RecordLayout::plain);
  EXPECT_EQ(test::read_text(path).substr(0, 8), "MAGIC001");
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
