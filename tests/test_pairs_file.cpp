// Pairs files (io/pairs_file.h): what `verify --pairs` reads and `verify --write-pairs`
// writes, and how a directory's files are matched to frames.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "error_of.h"
#include "harness/pairs/pairs_file.h"

namespace cdb {
namespace {

namespace fs = std::filesystem;

class PairsFile : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(testing::TempDir()) /
           ("pairs_file_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& bytes) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  // The message of the cdb::Error reading `file` throws.
  static std::string error_of(const fs::path& file, uint32_t faces) {
    return test::error_of([&] { read_pairs_file(file, faces); });
  }
  // The names of the directory's files matched to frames [first, last), in frame order.
  std::vector<std::string> matched(uint32_t first, uint32_t last) const {
    std::vector<std::string> names;
    for (const fs::path& p : pairs_files_for_frames(dir_, first, last)) names.push_back(p.filename().string());
    return names;
  }
  // The message of the cdb::Error matching them throws.
  std::string match_error(uint32_t first, uint32_t last) const {
    return test::error_of([&] { pairs_files_for_frames(dir_, first, last); });
  }
  fs::path dir_;
};

std::vector<std::pair<uint32_t, uint32_t>> plain(const std::vector<PrimPair>& pairs) {
  std::vector<std::pair<uint32_t, uint32_t>> out;
  for (const PrimPair p : pairs) out.emplace_back(p.a, p.b);
  return out;
}

using Pairs = std::vector<std::pair<uint32_t, uint32_t>>;

TEST_F(PairsFile, TextInEitherOrderWithCommentsCommasAndCarriageReturns) {
  const PairsRead r = read_pairs_file(
      write("a.txt", "# a comment\n\n5 2\n  0\t1\r\n3,4\n7 , 6\n# last\n9 8"), 10);
  EXPECT_EQ(plain(r.pairs), (Pairs{{0, 1}, {2, 5}, {3, 4}, {6, 7}, {8, 9}}));
  EXPECT_EQ(r.listed, 5u);
  EXPECT_EQ(r.duplicates, 0u);
}

TEST_F(PairsFile, DuplicatesInEitherOrderAreCountedOnceEach) {
  const PairsRead r = read_pairs_file(write("d.txt", "1 2\n2 1\n1 2\n3 4\n4 3\n"), 5);
  EXPECT_EQ(plain(r.pairs), (Pairs{{1, 2}, {3, 4}}));
  EXPECT_EQ(r.listed, 5u);
  EXPECT_EQ(r.duplicates, 3u);
  EXPECT_EQ(plain(r.first_duplicates), (Pairs{{1, 2}, {3, 4}}));
}

TEST_F(PairsFile, MalformedLinesNameFileAndLine) {
  const fs::path bad = write("bad.txt", "0 1\n# fine\n2 x\n");
  EXPECT_EQ(error_of(bad, 10), bad.string() + ":3: expected two triangle indices, got '2 x'");
  EXPECT_NE(error_of(write("one.txt", "0 1\n7\n"), 10).find("one.txt:2: expected two"), std::string::npos);
  EXPECT_NE(error_of(write("three.txt", "0 1 2\n"), 10).find("three.txt:1: expected two"), std::string::npos);
  EXPECT_NE(error_of(write("neg.txt", "-1 2\n"), 10).find("neg.txt:1: expected two"), std::string::npos);
}

TEST_F(PairsFile, OutOfRangeAndSelfPairsNameFileAndLine) {
  const fs::path range = write("range.txt", "0 1\n1 10\n");
  EXPECT_EQ(error_of(range, 10),
            range.string() + ":2: triangle 10 out of range (the scene has 10 triangles, 0-based)");
  EXPECT_NE(error_of(write("huge.txt", "99999999999 1\n"), 10).find("huge.txt:1: triangle >= 2^32-1 out of range"),
            std::string::npos);
  EXPECT_NE(error_of(write("self.txt", "\n\n4 4\n"), 10).find("self.txt:3: triangle 4 paired with itself"),
            std::string::npos);
}

TEST_F(PairsFile, BinaryReadsLittleEndianPairsAndChecksTheSize) {
  const uint32_t words[] = {3, 1, 0, 2, 1, 3};
  const PairsRead r = read_pairs_file(write("p.bin", std::string(reinterpret_cast<const char*>(words), sizeof words)), 4);
  EXPECT_EQ(plain(r.pairs), (Pairs{{0, 2}, {1, 3}}));
  EXPECT_EQ(r.duplicates, 1u);
  EXPECT_NE(error_of(write("odd.bin", std::string(12, '\0')), 4).find("12 bytes, not a whole number of pairs"),
            std::string::npos);
  const uint32_t far[] = {0, 1, 2, 9};
  EXPECT_NE(error_of(write("far.bin", std::string(reinterpret_cast<const char*>(far), sizeof far)), 4)
                .find("far.bin: pair 1 (byte 8): triangle 9 out of range"),
            std::string::npos);
}

TEST_F(PairsFile, WrittenFilesReadBackInBothFormats) {
  const std::vector<PrimPair> pairs = {{0, 3}, {1, 2}, {2, 7}};
  for (const char* name : {"frame_0003.txt", "frame_0003.bin"}) {
    write_pairs_file(dir_ / name, pairs, {"made by a test"});
    EXPECT_EQ(plain(read_pairs_file(dir_ / name, 8).pairs), plain(pairs)) << name;
  }
  EXPECT_EQ(fs::file_size(dir_ / "frame_0003.bin"), 3u * 8u);
  EXPECT_EQ(pairs_file_name(3, PairsFormat::text), "frame_0003.txt");
  EXPECT_EQ(pairs_file_name(12345, PairsFormat::binary), "frame_12345.bin");
}

TEST_F(PairsFile, NumberedFilesMatchTheirFramesAndOthersAreLeftAlone) {
  for (const char* name : {"frame_0.txt", "frame_0001.txt", "frame_2.bin", "frame_03.txt", "frame_9.txt"})
    write(name, "");
  EXPECT_EQ(matched(1, 4), (std::vector<std::string>{"frame_0001.txt", "frame_2.bin", "frame_03.txt"}));
  const std::string missing = match_error(3, 6);
  EXPECT_NE(missing.find("no pairs file for frame 4 (e.g. frame_0004.txt)"), std::string::npos) << missing;
  write("frame_002.txt", "");
  const std::string twice = match_error(0, 3);
  EXPECT_NE(twice.find("two pairs files for frame 2"), std::string::npos) << twice;
}

TEST_F(PairsFile, OtherNamesAreTakenInNaturalOrderOnePerFrame) {
  for (const char* name : {"out10.txt", "out9.txt", "out11.txt", ".hidden"}) write(name, "");
  EXPECT_EQ(matched(5, 8), (std::vector<std::string>{"out9.txt", "out10.txt", "out11.txt"}));
  const std::string short_of = match_error(0, 4);
  EXPECT_NE(short_of.find("3 files for the 4 frames 0:4"), std::string::npos) << short_of;
}

}  // namespace
}  // namespace cdb
