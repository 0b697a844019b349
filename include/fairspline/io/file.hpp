// Reading an input file whole, into memory the kernel may back with huge pages.
#pragma once

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace fairspline::io {

/// A file's bytes, read whole. Large ones (from 1 MiB) sit in memory aligned to and advised for
/// transparent huge pages: a std::string of an 8 MB input, zero-filled and then copied into, cost
/// ~2000 page faults of ~14 µs each on the measuring VM, ten times the reading.
class FileText {
 public:
  FileText() = default;
  std::string_view view() const noexcept { return {data_.get(), size_}; }
  std::size_t size() const noexcept { return size_; }

 private:
  struct Free {
    void operator()(char* p) const noexcept;
  };
  friend FileText read_file(const std::filesystem::path& path);
  friend FileText read_stream(std::FILE* stream, std::string_view name);
  /// The stream's bytes; `expected` is a first guess of their count (0: none).
  static FileText read(std::FILE* stream, std::size_t expected, const std::string& name);
  std::unique_ptr<char[], Free> data_;
  std::size_t size_ = 0;
};

/// Reads `path` whole. kIoError: "cannot read 'P': no such file or no access", "cannot read 'P':
/// it is a directory", "error while reading 'P'".
FileText read_file(const std::filesystem::path& path);

/// Reads an open stream to its end (standard input, a pipe); `name` is for the error message
/// ("error while reading NAME").
FileText read_stream(std::FILE* stream, std::string_view name);

}  // namespace fairspline::io
