#include "fairspline/io/file.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <system_error>
#include <utility>

#include "detail/huge_pages.hpp"
#include "fairspline/error.hpp"

namespace fairspline::io {

void FileText::Free::operator()(char* p) const noexcept {
  detail::FreeBlock{}(reinterpret_cast<std::byte*>(p));
}

FileText FileText::read(std::FILE* stream, std::size_t expected, const std::string& name) {
  detail::Block block = detail::take_block(std::max<std::size_t>(expected + 1, 64 << 10));
  std::size_t size = 0;
  for (;;) {
    if (size == block.size) {  // more than expected: a block twice as large, the bytes copied
      detail::Block larger = detail::take_block(2 * block.size);
      std::memcpy(larger.data.get(), block.data.get(), size);
      block = std::move(larger);
    }
    const std::size_t got = std::fread(block.data.get() + size, 1, block.size - size, stream);
    if (got == 0) break;
    size += got;
  }
  if (std::ferror(stream)) throw Error(ErrorCode::kIoError, "error while reading " + name);
  FileText text;
  text.data_.reset(reinterpret_cast<char*>(block.data.release()));  // (both std::free's)
  text.size_ = size;
  return text;
}

FileText read_file(const std::filesystem::path& path) {
  const std::string name = "'" + path.string() + "'";
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw Error(ErrorCode::kIoError, "cannot read " + name + ": it is a directory");
  }
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                             &std::fclose);
  if (!file)
    throw Error(ErrorCode::kIoError, "cannot read " + name + ": no such file or no access");
  const auto size = std::filesystem::file_size(path, ec);
  return FileText::read(file.get(), ec ? 0 : static_cast<std::size_t>(size), name);
}

FileText read_stream(std::FILE* stream, std::string_view name) {
  return FileText::read(stream, 0, std::string(name));
}

}  // namespace fairspline::io
