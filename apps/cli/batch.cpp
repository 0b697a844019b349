// `fairspline batch`: one fit request per input line in, one fit (or error) record per line and
// method out, in input order.
//
// Streaming: a block of lines (at most kBlockLines lines or about kBlockBytes bytes) is read,
// its lines are parsed, fitted and serialized in parallel (a fairspline::WorkerPool, started
// once for the run; each line writes its own output strings, so the order never depends on the
// threads), and the block is
// written in order on the writer's thread. A regular file's next block is read while this one
// is fitted; a pipe's after this one is submitted. Memory is bounded by two blocks of input and
// their output, whatever the length of the input.

#include "batch.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "fairspline/batch.hpp"
#include "fairspline/error.hpp"
#include "fairspline/fit.hpp"
#include "fairspline/io/json.hpp"
#include "fairspline/registry.hpp"
#include "fields.hpp"

namespace fairspline::cli {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

/// Lines per block (fewer when every line is fitted with several methods: see block_lines).
/// Small, so that two blocks of input and their records stay in the caches' reach and are
/// mapped in once: 20-point lines took 80 MB and 1.75 s for 10^5 lines in blocks of 4096, 16 MB
/// and 1.55 s in blocks of 512 (docs/architecture.md, "Batch").
constexpr std::size_t kBlockLines = 512;
/// A block stops growing once its input text reaches this size (a longer line is still read
/// whole).
constexpr std::size_t kBlockBytes = std::size_t{1} << 20;
/// Redraw interval of the progress line.
constexpr auto kRedrawInterval = std::chrono::milliseconds(200);

// strerror_r is the thread-safe strerror (writes happen on the writer thread); the GNU version
// returns the text, the POSIX one an error code.
[[maybe_unused]] const char* strerror_r_text(const char* text, const char*) {
  return text;
}
[[maybe_unused]] const char* strerror_r_text(int status, const char* buf) {
  return status == 0 ? buf : "unknown error";
}

std::string system_error_text(int err) {
  char buf[256] = "";
  return strerror_r_text(strerror_r(err, buf, sizeof buf), buf);
}

// ---------------------------------------------------------------- input

/// Reads a file descriptor line by line through one large buffer.
class LineReader {
 public:
  LineReader(int fd, std::string name) : fd_(fd), name_(std::move(name)), buf_(1 << 20) {}

  /// True when the next read would wait for a writer (a pipe or terminal with nothing
  /// buffered): the lines already read are then fitted first, so that a slow producer does not
  /// hold back records until a whole block has arrived.
  bool would_wait() const {
    if (pos_ != end_ || eof_) return false;
    pollfd p{fd_, POLLIN, 0};
    return ::poll(&p, 1, 0) == 0;
  }

  /// Appends the next line to `out` (without its '\n' or a '\r' before it) and sets `raw` to
  /// the bytes it took in the input; returns false at the end of the input.
  bool next(std::string& out, std::size_t& raw) {
    const std::size_t start = out.size();
    raw = 0;
    for (;;) {
      if (pos_ == end_ && !fill()) break;
      const char* begin = buf_.data() + pos_;
      const auto* newline = static_cast<const char*>(std::memchr(begin, '\n', end_ - pos_));
      const std::size_t take =
          newline != nullptr ? static_cast<std::size_t>(newline - begin) : end_ - pos_;
      out.append(begin, take);
      pos_ += take;
      raw += take;
      if (newline != nullptr) {
        ++pos_;
        ++raw;
        break;
      }
    }
    if (raw == 0) return false;
    if (out.size() > start && out.back() == '\r') out.pop_back();
    return true;
  }

 private:
  bool fill() {
    if (eof_) return false;
    ssize_t n;
    do {
      n = ::read(fd_, buf_.data(), buf_.size());
    } while (n < 0 && errno == EINTR);
    if (n < 0) {
      throw Error(ErrorCode::kIoError,
                  "error while reading " + name_ + ": " + system_error_text(errno));
    }
    pos_ = 0;
    end_ = static_cast<std::size_t>(n);
    eof_ = n == 0;
    return !eof_;
  }

  int fd_;
  std::string name_;
  std::vector<char> buf_;
  std::size_t pos_ = 0, end_ = 0;
  bool eof_ = false;
};

/// The input file (or standard input), open.
struct Input {
  int fd = STDIN_FILENO;
  std::string name = "standard input";
  std::optional<std::uint64_t> size;  ///< bytes left to read, when the input is a regular file

  Input() = default;
  Input(const Input&) = delete;
  Input& operator=(const Input&) = delete;
  ~Input() {
    if (fd != STDIN_FILENO) ::close(fd);
  }
};

void open_input(const std::string& path, Input& in) {
  if (!path.empty() && path != "-") {
    in.name = "'" + path + "'";
    in.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (in.fd < 0) {
      const int err = errno;
      in.fd = STDIN_FILENO;
      throw Error(ErrorCode::kIoError, "cannot read " + in.name + ": " + system_error_text(err));
    }
  }
  struct stat st {};
  if (::fstat(in.fd, &st) == 0) {
    if (S_ISDIR(st.st_mode)) {
      throw Error(ErrorCode::kIoError, "cannot read " + in.name + ": it is a directory");
    }
    if (S_ISREG(st.st_mode)) {
      const off_t at = ::lseek(in.fd, 0, SEEK_CUR);  // standard input may start mid-file
      const auto size = static_cast<std::uint64_t>(st.st_size);
      const auto done = static_cast<std::uint64_t>(std::max<off_t>(at, 0));
      in.size = size > done ? size - done : 0;
    }
  }
}

/// One input line of a block: its text is block.text[offset, offset + size).
struct Line {
  std::size_t offset = 0;
  std::size_t size = 0;
  std::size_t number = 0;  ///< 1-based line number in the input
  std::size_t raw_bytes = 0;
};

struct Block {
  std::string text;
  std::vector<Line> lines;
  std::uint64_t skipped_bytes = 0;  ///< bytes of blank and comment lines
  bool last = false;                ///< the input ended within this block
};

bool is_skipped(std::string_view line) {
  const auto first = line.find_first_not_of(" \t\r\f\v");
  return first == std::string_view::npos || line[first] == '#';
}

/// Reads up to `max_lines` lines to fit into `block`; `line_number` counts every line read.
void read_block(LineReader& reader, std::size_t max_lines, std::size_t& line_number, Block& block) {
  block.text.clear();
  block.lines.clear();
  block.skipped_bytes = 0;
  while (block.lines.size() < max_lines && block.text.size() < kBlockBytes) {
    if (!block.lines.empty() && reader.would_wait()) return;
    const std::size_t start = block.text.size();
    std::size_t raw = 0;
    if (!reader.next(block.text, raw)) {
      block.last = true;
      return;
    }
    ++line_number;
    if (is_skipped(std::string_view(block.text).substr(start))) {
      block.text.resize(start);
      block.skipped_bytes += raw;
      continue;
    }
    block.lines.push_back({start, block.text.size() - start, line_number, raw});
  }
}

// ---------------------------------------------------------------- output

/// The output file (or standard output), open for buffered writing.
class Output {
 public:
  explicit Output(const std::string& path) {
    if (path.empty() || path == "-") {
      file_ = stdout;
      name_ = "standard output";
    } else {
      name_ = "'" + path + "'";
      file_ = std::fopen(path.c_str(), "wb");
      if (file_ == nullptr) {
        throw Error(ErrorCode::kIoError, "cannot write " + name_ + ": " + system_error_text(errno));
      }
    }
    std::setvbuf(file_, nullptr, _IOFBF, std::size_t{1} << 20);
  }
  Output(const Output&) = delete;
  Output& operator=(const Output&) = delete;
  ~Output() {
    if (file_ != nullptr && file_ != stdout) std::fclose(file_);
  }

  bool is_stdout() const { return file_ == stdout; }

  /// Writes `texts` in order straight from their strings, up to IOV_MAX at a time with
  /// writev: fwrite copied every record into the stdio buffer first (~5% of a run's CPU).
  void write_all(const std::vector<std::string>& texts) {
    if (std::fflush(file_) != 0) fail();  // what fwrite buffered goes first
    const int fd = ::fileno(file_);
    std::vector<iovec> io;
    io.reserve(std::min<std::size_t>(texts.size(), IOV_MAX));
    for (std::size_t i = 0; i < texts.size();) {
      io.clear();
      for (; i < texts.size() && io.size() < IOV_MAX; ++i) {
        if (!texts[i].empty()) {
          io.push_back({const_cast<char*>(texts[i].data()), texts[i].size()});
        }
      }
      write_vector(fd, io);
    }
  }

  /// Hands what is buffered to the file or pipe.
  void flush() {
    if (std::fflush(file_) != 0) fail();
  }

  /// Flushes (and closes a file), reporting any error of the writes before.
  void finish() {
    if (std::fflush(file_) != 0 || std::ferror(file_)) fail();
    if (file_ != stdout) {
      std::FILE* f = std::exchange(file_, nullptr);
      if (std::fclose(f) != 0) fail();
    }
  }

 private:
  /// All of io's bytes, through short writes and interruptions.
  void write_vector(int fd, std::vector<iovec>& io) {
    iovec* v = io.data();
    std::size_t left = io.size();
    while (left > 0) {
      const ssize_t n = ::writev(fd, v, static_cast<int>(left));
      if (n < 0) {
        if (errno == EINTR) continue;
        fail();
      }
      auto done = static_cast<std::size_t>(n);
      while (left > 0 && done >= v->iov_len) {
        done -= v->iov_len;
        ++v;
        --left;
      }
      if (left > 0) {
        v->iov_base = static_cast<char*>(v->iov_base) + done;
        v->iov_len -= done;
      }
    }
  }

  [[noreturn]] void fail() {
    throw Error(ErrorCode::kIoError,
                "error while writing " + name_ + ": " + system_error_text(errno));
  }

  std::FILE* file_ = nullptr;
  std::string name_;
};

/// Writes blocks of records on its own thread, so that writing one block overlaps fitting the
/// next (on a 2-core machine the serial write otherwise took ~10% of a run to /dev/null and
/// more to a file). One block is written at a time, in submission order.
class BlockWriter {
 public:
  explicit BlockWriter(Output& output) : output_(output), thread_([this] { run(); }) {}
  BlockWriter(const BlockWriter&) = delete;
  BlockWriter& operator=(const BlockWriter&) = delete;
  ~BlockWriter() {
    {
      const std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }

  /// Waits until the previous block is written, then takes `records` to write (with a flush
  /// after it if `flush`) and gives back the strings of the previous block in their place, to
  /// be reused. Rethrows the error of an earlier write.
  void submit(std::vector<std::string>& records, bool flush) {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [this] { return !pending_; });
    if (failure_) std::rethrow_exception(failure_);
    records.swap(block_);
    flush_ = flush;
    pending_ = true;
    lock.unlock();
    wake_.notify_all();
  }

  /// Waits until everything submitted is written; rethrows a write error.
  void drain() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [this] { return !pending_; });
    if (failure_) std::rethrow_exception(failure_);
  }

 private:
  void run() {
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return pending_ || stop_; });
      if (!pending_) return;
      lock.unlock();
      try {
        output_.write_all(block_);
        for (std::string& r : block_) {
          if (r.capacity() > kKeepTextCapacity) std::string().swap(r);  // after a huge one
        }
        if (flush_) output_.flush();
      } catch (...) {
        const std::lock_guard relock(mutex_);
        if (!failure_) failure_ = std::current_exception();
      }
      lock.lock();
      pending_ = false;
      idle_.notify_all();
    }
  }

  Output& output_;
  std::vector<std::string> block_;
  bool flush_ = false;
  bool pending_ = false;
  bool stop_ = false;
  std::exception_ptr failure_;
  std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::thread thread_;  // last: starts after everything it reads is initialized
};

// ---------------------------------------------------------------- progress

std::string format_duration(double seconds) {
  const auto s = static_cast<long long>(seconds + 0.5);
  char buf[32];
  if (s >= 3600) {
    std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%lld:%02lld", s / 60, s % 60);
  }
  return buf;
}

/// A single progress line on stderr (a terminal), redrawn by its own thread every
/// kRedrawInterval: records done, records per second, and for a regular file the share of the
/// input read and the time left estimated from it.
class Progress {
 public:
  explicit Progress(std::optional<std::uint64_t> total_bytes)
      : total_bytes_(total_bytes), start_(Clock::now()), thread_([this] { run(); }) {}
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  ~Progress() { stop(); }

  /// Called by workers as lines finish; `bytes` are input bytes consumed.
  void add(std::size_t records, std::uint64_t bytes) {
    records_.fetch_add(records, std::memory_order_relaxed);
    bytes_.fetch_add(bytes, std::memory_order_relaxed);
  }

  /// Stops redrawing and leaves a final line (records, time, rate) ending in a newline.
  void stop() {
    {
      const std::lock_guard lock(mutex_);
      if (stopped_) return;
      stopped_ = true;
    }
    wake_.notify_all();
    thread_.join();
    draw(true);
  }

 private:
  void run() {
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, kRedrawInterval, [this] { return stopped_; })) draw(false);
  }

  void draw(bool final) const {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const std::size_t records = records_.load(std::memory_order_relaxed);
    const std::uint64_t bytes = bytes_.load(std::memory_order_relaxed);
    const double rate = elapsed > 0 ? static_cast<double>(records) / elapsed : 0.0;
    char line[160];
    if (final) {
      std::snprintf(line, sizeof line,
                    "\rfairspline batch: %zu records in %s (%.0f records/s)\x1b[K\n", records,
                    format_duration(elapsed).c_str(), rate);
    } else if (total_bytes_ && *total_bytes_ > 0 && bytes > 0) {
      const double share = std::min(1.0, static_cast<double>(bytes) / *total_bytes_);
      const double left = elapsed * (1.0 - share) / share;
      std::snprintf(
          line, sizeof line,
          "\rfairspline batch: %zu records, %.0f records/s, %.0f%% of input, ETA %s\x1b[K", records,
          rate, 100.0 * share, format_duration(left).c_str());
    } else {
      std::snprintf(line, sizeof line, "\rfairspline batch: %zu records, %.0f records/s\x1b[K",
                    records, rate);
    }
    std::fputs(line, stderr);
    std::fflush(stderr);
  }

  const std::optional<std::uint64_t> total_bytes_;
  const Clock::time_point start_;
  std::atomic<std::size_t> records_{0};
  std::atomic<std::uint64_t> bytes_{0};
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopped_ = false;
  std::thread thread_;  // last: starts after everything it reads is initialized
};

// ---------------------------------------------------------------- fitting

/// What every line of a batch is fitted with.
struct Plan {
  std::vector<std::string> methods;  ///< -m; empty: the line's method or the default
  ReportLevel level = ReportLevel::kBasic;
  FitFlags flags;
  FieldSelection fields;  ///< what a fit record keeps; empty: all of it
  std::size_t records_per_line() const { return std::max<std::size_t>(1, methods.size()); }
};

std::string dump_line(json& record, std::size_t line_number) {
  record["line"] = line_number;
  std::string text = record.dump(-1, ' ', false, json::error_handler_t::replace);
  text += '\n';
  return text;
}

/// The record of a fit: what `fairspline fit` writes (io::write_json), with "line" among its
/// keys, cut down to `fields` unless empty, appended to `out` (whose memory is reused from
/// record to record).
void append_fit_record(std::string& out, const FitResult& r, std::size_t line_number,
                       const FieldSelection& fields) {
  thread_local json extra = {{"line", 0}};
  extra["line"] = line_number;
  append_fit_text(out, r, fields, extra);
  out += '\n';
}

/// A JSON syntax error names line 1 of the one-line text; say which line of the input it is
/// (the index of a kParseError is the line, as for a whole file).
Error in_input_terms(const Error& e, std::size_t line_number) {
  constexpr std::string_view kPrefix = "invalid JSON at line 1, ";
  const std::string_view message = e.what();
  if (e.code() != ErrorCode::kParseError || !message.starts_with(kPrefix)) return e;
  return Error(ErrorCode::kParseError,
               "invalid JSON at line " + std::to_string(line_number) + ", " +
                   std::string(message.substr(kPrefix.size())),
               line_number);
}

std::string error_record(const Error& e, std::size_t line_number, json method) {
  json record = io::error_to_json(e);
  record["method"] = std::move(method);
  return dump_line(record, line_number);
}

/// Parses and fits one line with every method of the plan, writing one record per method to
/// out[0..plan.records_per_line()). Returns the number of failed records.
std::size_t fit_line(std::string_view text, std::size_t line_number, const Plan& plan,
                     FitResult& scratch, std::string* out) {
  const std::size_t records = plan.records_per_line();
  io::ParsedInput parsed;
  try {
    parsed = io::parse_json_input(text);
  } catch (const Error& e) {
    const Error error = in_input_terms(e, line_number);
    for (std::size_t m = 0; m < records; ++m) {
      out[m] = error_record(error, line_number,
                            plan.methods.empty() ? json(nullptr) : json(plan.methods[m]));
    }
    return records;
  }
  FitOptions fit_options = parsed.fit_options(plan.level);
  plan.flags.apply(fit_options);
  std::size_t failed = 0;
  for (std::size_t m = 0; m < records; ++m) {
    const std::string_view method = !plan.methods.empty() ? std::string_view(plan.methods[m])
                                    : parsed.method       ? std::string_view(*parsed.method)
                                                          : default_method_name();
    try {
      fit_into(method, parsed.input, parsed.options, fit_options, scratch);
      out[m].clear();
      append_fit_record(out[m], scratch, line_number, plan.fields);
    } catch (const Error& e) {
      out[m] = error_record(e, line_number, json(std::string(method)));
      ++failed;
    } catch (const std::exception& e) {
      // Not a user error (e.g. out of memory): still one record, never lost (as in fit_many).
      const Error error(ErrorCode::kInvalidArgument,
                        std::string("unexpected failure: ") + e.what());
      out[m] = error_record(error, line_number, json(std::string(method)));
      ++failed;
    }
  }
  return failed;
}

}  // namespace

int run_batch(const BatchArgs& args) {
  Plan plan;
  plan.level = io::parse_report_level(args.report);
  plan.flags = args.flags;
  plan.fields = parse_fields(args.fields, plan.level);
  for (const std::string& m : args.methods) {
    plan.methods.emplace_back(find_method(m).name);  // unknown names fail before any work
  }
  Input input;
  open_input(args.input, input);
  Output output(args.output);
  const bool show_progress = !args.quiet && ::isatty(STDERR_FILENO) == 1 &&
                             !(output.is_stdout() && ::isatty(STDOUT_FILENO) == 1);
  std::optional<Progress> progress;
  if (show_progress) progress.emplace(input.size);

  LineReader reader(input.fd, input.name);
  const std::size_t per_line = plan.records_per_line();
  const std::size_t block_lines = std::max<std::size_t>(64, kBlockLines / per_line);
  BlockWriter writer(output);
  WorkerPool pool(args.threads);
  Block block, ahead;
  std::vector<std::string> records;
  std::size_t line_number = 0, total = 0;
  std::atomic<std::size_t> failed{0};
  // A regular file's next block is read while this one's lines are fitted (work item 0, on
  // whichever thread takes it): read between blocks, it left the other cores idle (~5% of a run
  // on two). Not from a pipe or terminal, where reading may wait for a producer while this
  // block's records are ready.
  const bool read_ahead = input.size.has_value();
  std::exception_ptr read_error;
  read_block(reader, block_lines, line_number, block);
  for (;;) {
    if (progress) progress->add(0, block.skipped_bytes);
    const std::size_t lines = block.lines.size();
    records.resize(lines * per_line);
    const std::size_t first = read_ahead && !block.last ? 1 : 0;
    pool.run(first + lines, [&](std::size_t k) {
      if (k < first) {
        try {  // (rethrown once this block's records are submitted, as before)
          read_block(reader, block_lines, line_number, ahead);
        } catch (...) {
          read_error = std::current_exception();
        }
        return;
      }
      thread_local FitResult scratch;  // fit_into reuses its vectors from line to line
      const std::size_t i = k - first;
      const Line& line = block.lines[i];
      const std::string_view text = std::string_view(block.text).substr(line.offset, line.size);
      const std::size_t f = fit_line(text, line.number, plan, scratch, &records[i * per_line]);
      if (f != 0) failed.fetch_add(f, std::memory_order_relaxed);
      if (progress) progress->add(per_line, line.raw_bytes);
    });
    total += records.size();
    // A reader downstream gets what there is when the input would make us wait.
    writer.submit(records, reader.would_wait());
    if (read_error) std::rethrow_exception(read_error);
    if (block.last) break;
    if (first != 0) {
      std::swap(block, ahead);
    } else {
      read_block(reader, block_lines, line_number, block);
    }
  }
  writer.drain();
  output.finish();
  if (progress) progress->stop();
  if (failed.load() != 0) {
    std::fprintf(stderr, "fairspline batch: %zu of %zu records failed\n", failed.load(), total);
    return 1;
  }
  return 0;
}

}  // namespace fairspline::cli
