#include "fairspline/io/file.hpp"

#include <unistd.h>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "test_util.hpp"

#include "fairspline/error.hpp"

namespace fairspline::io {
namespace {

using fairspline::testing::expect_error;
namespace fs = std::filesystem;

fs::path scratch_dir() {
  const fs::path dir =
      fs::temp_directory_path() / ("fairspline-file-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string random_bytes(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (char& c : s) c = static_cast<char>(rng());
  return s;
}

TEST(ReadFile, GivesTheBytesOfSmallEmptyAndLargeFiles) {
  const fs::path dir = scratch_dir();
  // 0 bytes, under the first block, and over 1 MiB (a huge-page block, and not a multiple of it).
  for (const std::size_t n : {std::size_t{0}, std::size_t{17}, std::size_t{3} << 20 | 5}) {
    const std::string bytes = random_bytes(n, static_cast<unsigned>(n));
    const fs::path path = dir / ("f" + std::to_string(n));
    std::ofstream(path, std::ios::binary) << bytes;
    const FileText text = read_file(path);
    EXPECT_EQ(text.size(), n);
    EXPECT_TRUE(text.view() == bytes) << n;
    if (n >= (std::size_t{1} << 20)) {
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(text.view().data()) % (std::size_t{2} << 20), 0u);
    }
  }
  fs::remove_all(dir);
}

TEST(ReadStream, GrowsPastItsFirstGuess) {
  // A stream of unknown size starts with a 64 KiB block: 300 KiB takes three doublings.
  const std::string bytes = random_bytes(300 << 10, 7);
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
  std::rewind(f);
  const FileText text = read_stream(f, "standard input");
  std::fclose(f);
  EXPECT_TRUE(text.view() == bytes);
}

TEST(ReadFile, ErrorsNameThePath) {
  expect_error(ErrorCode::kIoError, [] { read_file("/nonexistent/points.csv"); },
               {"cannot read '/nonexistent/points.csv': no such file or no access"});
  const fs::path dir = scratch_dir();
  expect_error(ErrorCode::kIoError, [&] { read_file(dir); },
               {"cannot read '" + dir.string() + "': it is a directory"});
  fs::remove_all(dir);
  // A stream that fails while being read (one opened for writing only).
  std::FILE* f = std::fopen("/dev/null", "w");
  ASSERT_NE(f, nullptr);
  expect_error(ErrorCode::kIoError, [&] { read_stream(f, "standard input"); },
               {"error while reading standard input"});
  std::fclose(f);
}

}  // namespace
}  // namespace fairspline::io
