// The one serializer of a FitResult (io/json.hpp: write_json, to_json).
//
// The fields are listed once, in emit_result / emit_report / emit_method_report, which write
// into a sink: TextSink writes the JSON text (what the CLI, the batch tool, the web server and
// Python's to_json give), SaxSink gives the same document as nlohmann SAX events (what Python
// builds its dicts from); to_json parses the text. Members are written in the order nlohmann's
// object (a std::map) sorts them, and numbers as its dump() writes them, so that the text is
// byte for byte to_json(result).dump(indent) without building that tree: for a 20-point fit
// (~300 numbers, each a node) building, dumping and freeing the tree took 80% of a batch.

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include "detail/huge_pages.hpp"
#include "detail/json_input.hpp"
#include "detail/number_format.hpp"
#include "fairspline/io/json.hpp"

namespace fairspline::io {

using nlohmann::json;

namespace {

/// Gives `out` room for `capacity` characters, keeping its first `used`. Storage of 1 MiB and
/// more is advised for huge pages before the text is copied in, and is only mapped in as it is
/// written: faulted in 4 KiB at a time (and zero-filled whole at each doubling), writing 2·10^5
/// points into a string (the server's responses, Python's to_json) took 463 ms against 65–79 ms
/// to a stream (bench/json_io_bench.cpp).
void reserve_text(std::string& out, std::size_t used, std::size_t capacity) {
  if (capacity <= out.capacity()) return;
  if (capacity < detail::kAlignedBlockMinBytes) {
    out.reserve(capacity);
    return;
  }
  std::string larger;
  larger.reserve(capacity);
  detail::advise_huge_pages(larger.data(), capacity);
  larger.append(out.data(), std::min(used, out.size()));
  out.swap(larger);
}

/// Writes JSON text into a string, compact or indented as dump(indent) does.
///
/// The string is kept sized past what is written (p_ is the end of the text) and written
/// through a pointer: a number goes straight from the digit generator into it, where appending
/// it, and each comma and bracket, cost a capacity check and call per character (a third of
/// the writing time). The spare is cut off when the sink is destroyed.
class TextSink {
 public:
  TextSink(std::string& out, int indent)
      : out_(out), indent_(indent), p_(out.data() + out.size()), end_(p_) {}
  /// Writes to `stream` whenever kFlushBytes are buffered (and at flush()): a long curve's text
  /// is never held whole (57 MB for 2·10^5 points), nor regrown and copied.
  TextSink(std::string& buffer, int indent, std::ostream& stream)
      : out_(buffer), indent_(indent), stream_(&stream) {
    out_.resize(kFlushBytes + 4096);
    p_ = out_.data();
    end_ = p_ + out_.size();
  }
  TextSink(const TextSink&) = delete;
  TextSink& operator=(const TextSink&) = delete;
  ~TextSink() { out_.resize(stream_ ? 0 : used()); }

  void flush() {
    if (!stream_) return;
    stream_->write(out_.data(), static_cast<std::streamsize>(used()));
    p_ = out_.data();
    if (!*stream_) throw Error(ErrorCode::kIoError, "error while writing the JSON text");
  }

  void begin_object() { open('{'); }
  void end_object() { close('}'); }
  void begin_array() { open('['); }
  void end_array() { close(']'); }

  /// A key spelled in this file: a literal of plain ASCII (nothing to escape, nothing to check).
  template <std::size_t N>
  void key(const char (&k)[N]) {
    key(std::string_view(k, N - 1), true);
  }
  void key(std::string_view k) { key(k, is_plain(k)); }

  void null() {
    before_value();
    put("null");
  }
  void boolean(bool b) {
    before_value();
    put(b ? std::string_view("true") : std::string_view("false"));
  }
  void number(double v) {
    before_value();
    p_ = write_number(room(detail::kJsonNumberChars), v);
    if (stream_ && used() >= kFlushBytes) flush();
  }
  /// [x, y]: compact, in one go (a fit is mostly pairs: points, control points, tangents).
  void pair(Vec2 v) {
    if (indent_ >= 0) {
      begin_array();
      number(v.x);
      number(v.y);
      end_array();
      return;
    }
    before_value();
    char* p = room(2 * detail::kJsonNumberChars + 3);
    *p = '[';
    p = write_number(p + 1, v.x);
    *p = ',';
    p = write_number(p + 1, v.y);
    *p = ']';
    p_ = p + 1;
    first_ = false;
    if (stream_ && used() >= kFlushBytes) flush();
  }
  void integer(std::int64_t v) { append_integer(v); }
  void unsigned_integer(std::uint64_t v) { append_integer(v); }
  void string(std::string_view s) {
    before_value();
    write_string(s);
  }

  /// An array of n elements, element i written by emit(sink, i). A long one in a compact text
  /// is written in chunks on up to four cores and joined in order, the same text: formatting
  /// numbers is most of the writing of a long curve (2·10^5 points: 60 ms, a quarter of
  /// `fairspline fit`'s process).
  template <class Emit>
  void array(std::size_t n, const Emit& emit) {
    begin_array();
    elements(n, emit);
    end_array();
  }

  /// A value this writer does not spell out (binary, discarded): as dump() writes it.
  void other(const json& v) {
    before_value();
    put(v.dump(-1, ' ', false, json::error_handler_t::replace));
  }

 private:
  std::size_t used() const { return static_cast<std::size_t>(p_ - out_.data()); }

  /// The text of v at p (which has room for kJsonNumberChars), from the memo or formatted;
  /// returns its end.
  char* write_number(char* p, double v) {
    const auto bits = std::bit_cast<std::uint64_t>(v);
    NumberMemo::Entry& e = memo_.slots[(bits * 0x9E3779B97F4A7C15u) >> (64 - NumberMemo::kBits)];
    if (e.bits == bits) {
      std::memcpy(p, e.text, sizeof e.text);
      return p + e.size;
    }
    char* end = detail::format_json_number(p, v);
    const auto size = static_cast<std::size_t>(end - p);
    if (size <= sizeof e.text) {
      e.bits = bits;
      e.size = static_cast<std::uint8_t>(size);
      std::memcpy(e.text, p, sizeof e.text);
    }
    return end;
  }

  /// Room for n more characters at p_.
  char* room(std::size_t n) {
    if (static_cast<std::size_t>(end_ - p_) < n) grow(n);
    return p_;
  }
  /// Sizes the string a chunk further (zero-filling only that, not the whole capacity a string
  /// reused from record to record has; an eighth of the text, 512 B to 1 MiB, so that a long
  /// text comes here rarely), reallocating to twice the capacity when it is full.
  [[gnu::noinline]] void grow(std::size_t n) {
    const std::size_t at = used();
    const std::size_t chunk = std::clamp<std::size_t>(at / 8, 512, std::size_t{1} << 20);
    const std::size_t want = at + n + chunk;
    if (want > out_.capacity()) reserve_text(out_, at, std::max(want, 2 * out_.capacity()));
    out_.resize(want);
    p_ = out_.data() + at;
    end_ = out_.data() + out_.size();
  }
  void put(char c) {
    *room(1) = c;
    ++p_;
  }
  void put(std::string_view s) {
    std::memcpy(room(s.size()), s.data(), s.size());
    p_ += s.size();
  }
  /// Text of any length (a chunk of elements): never growing a stream's buffer; a long one
  /// straight to the stream.
  void raw(std::string_view s) {
    if (stream_ && used() + s.size() > kFlushBytes) {
      flush();
      if (s.size() >= kFlushBytes / 4) {
        stream_->write(s.data(), static_cast<std::streamsize>(s.size()));
        if (!*stream_) throw Error(ErrorCode::kIoError, "error while writing the JSON text");
        return;
      }
    }
    put(s);
  }

  template <class Int>
  void append_integer(Int v) {
    before_value();
    constexpr std::size_t kDigits = 24;
    char* p = room(kDigits);
    p_ = std::to_chars(p, p + kDigits, v).ptr;
  }

  /// Before a value: nothing after a key, else the separator of an array element.
  void before_value() {
    if (after_key_) {
      after_key_ = false;
      return;
    }
    separate();
  }

  /// The comma before all but the first member or element, and the line break when indenting.
  void separate() {
    if (!first_) put(',');
    first_ = false;
    if (indent_ >= 0 && depth_ > 0) newline();
  }

  void open(char c) {
    before_value();
    put(c);
    ++depth_;
    first_ = true;
  }

  /// Empty containers stay "{}" and "[]" (as dump(indent)).
  void close(char c) {
    --depth_;
    if (!first_ && indent_ >= 0) newline();
    put(c);
    first_ = false;
  }

  void newline() {
    const std::size_t spaces = static_cast<std::size_t>(depth_) * static_cast<std::size_t>(indent_);
    char* p = room(spaces + 1);
    *p = '\n';
    std::memset(p + 1, ' ', spaces);
    p_ += spaces + 1;
  }

  static bool is_plain(std::string_view s) {
    for (const char c : s) {
      const auto u = static_cast<unsigned char>(c);
      if (u < 0x20 || u >= 0x80 || c == '"' || c == '\\') return false;
    }
    return true;
  }

  void key(std::string_view k, bool plain) {
    if (indent_ < 0 && plain) {  // compact: ,"key": in one go
      char* p = room(k.size() + 4);
      if (!first_) *p++ = ',';
      first_ = false;
      *p = '"';
      std::memcpy(p + 1, k.data(), k.size());
      p[k.size() + 1] = '"';
      p[k.size() + 2] = ':';
      p_ = p + k.size() + 3;
    } else {
      separate();
      write_string(k, plain);
      put(indent_ < 0 ? std::string_view(":") : std::string_view(": "));
    }
    after_key_ = true;
  }

  /// A quoted string; one with anything but printable ASCII other than '"' and '\' goes through
  /// dump() (its escapes, and invalid UTF-8 replaced by U+FFFD, never an exception).
  void write_string(std::string_view s) { write_string(s, is_plain(s)); }
  void write_string(std::string_view s, bool plain) {
    if (plain) {
      char* p = room(s.size() + 2);
      *p = '"';
      std::memcpy(p + 1, s.data(), s.size());
      p[s.size() + 1] = '"';
      p_ += s.size() + 2;
    } else {
      put(json(std::string(s)).dump(-1, ' ', false, json::error_handler_t::replace));
    }
  }

  static constexpr std::size_t kFlushBytes = 1 << 20;
  /// Arrays of array() from this length on are written on several cores, in chunks of
  /// kChunkItems (a thread costs ~50 µs to start; a chunk of segments, ~300 KB of text, takes
  /// ~300 µs to format and stays in the cache; chunks of 4096 took 4 times the fresh memory).
  static constexpr std::size_t kParallelItems = 1 << 14, kChunkItems = 1024;

  /// The text of recently written numbers by their bits, per thread (the text is a function of
  /// the bits, so entries never go stale). A fit writes most numbers twice or more: a segment's
  /// first control point is the point (and the previous segment's last), its t0 and t1 are knots;
  /// for a 20-point record 6 of every 10 numbers of a segment are copied instead of formatted.
  struct NumberMemo {
    static constexpr int kBits = 9;
    struct Entry {
      std::uint64_t bits = 0;  // starts as 0.0's entry, a true one
      std::uint8_t size = 3;
      char text[23] = {'0', '.', '0'};
    };
    std::array<Entry, std::size_t{1} << kBits> slots;
  };
  static NumberMemo& thread_memo() {
    thread_local NumberMemo memo;
    return memo;
  }

  /// The elements of array(), the array just opened.
  template <class Emit>
  void elements(std::size_t n, const Emit& emit) {
    const std::size_t chunks = (n + kChunkItems - 1) / kChunkItems;
    const std::size_t threads =
        indent_ < 0 && n >= kParallelItems
            ? std::min<std::size_t>({chunks, std::max(1u, std::thread::hardware_concurrency()), 4})
            : 1;
    if (threads < 2) {
      for (std::size_t i = 0; i < n; ++i) emit(*this, i);
      return;
    }
    // Chunk k is this thread's when k % threads == 0, written in place; the others' go through a
    // ring of 2·threads texts: a worker waits for its slot to be written out before reusing it.
    const std::size_t ring = 2 * threads;
    // (Kept for the sink's next long array: their texts' memory is mapped in already.)
    if (ring_size_ < ring) {
      ring_ = std::make_unique<Slot[]>(ring);
      ring_size_ = ring;
    }
    Slot* const slots = ring_.get();
    for (std::size_t k = 0; k < ring; ++k) {
      slots[k].error = nullptr;
      slots[k].ready.store(0);
    }
    std::atomic<std::size_t> written{0};
    std::atomic<bool> stop{false};
    const auto range = [&](std::size_t k) {
      return std::pair{k * kChunkItems, std::min(n, (k + 1) * kChunkItems)};
    };
    const auto work = [&](std::size_t first) {
      for (std::size_t k = first; k < chunks; k += threads) {
        for (std::size_t w = written.load(); w + ring < k + 1; w = written.load()) {
          if (stop.load()) return;
          written.wait(w);
        }
        Slot& slot = slots[k % ring];
        try {
          slot.text.clear();
          TextSink sink(slot.text, -1);
          const auto [lo, hi] = range(k);
          for (std::size_t i = lo; i < hi; ++i) emit(sink, i);
        } catch (...) {
          slot.error = std::current_exception();
        }
        slot.ready.store(k + 1);
        slot.ready.notify_one();
      }
    };
    std::vector<std::jthread> pool;
    // (Declared after the pool: runs first on the way out, so that no worker waits forever.)
    const auto release = [&](void*) {
      stop.store(true);
      written.fetch_add(ring);
      written.notify_all();
    };
    const std::unique_ptr<void, decltype(release)> guard(this, release);
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(work, t);
    for (std::size_t k = 0; k < chunks; ++k) {
      if (k % threads == 0) {
        const auto [lo, hi] = range(k);
        for (std::size_t i = lo; i < hi; ++i) emit(*this, i);
      } else {
        Slot& slot = slots[k % ring];
        for (std::size_t r = slot.ready.load(); r != k + 1; r = slot.ready.load()) {
          slot.ready.wait(r);
        }
        if (slot.error) std::rethrow_exception(slot.error);
        separate();
        raw(slot.text);
      }
      written.store(k + 1);
      written.notify_all();
    }
  }

  /// A chunk of array() formatted by another thread.
  struct Slot {
    std::string text;
    std::exception_ptr error;
    std::atomic<std::size_t> ready{0};  // the chunk's index + 1 once its text is in
  };

  std::string& out_;
  NumberMemo& memo_ = thread_memo();
  std::unique_ptr<Slot[]> ring_;
  std::size_t ring_size_ = 0;
  const int indent_;
  std::ostream* stream_ = nullptr;
  char* p_ = nullptr;    ///< the end of the text in out_
  char* end_ = nullptr;  ///< the end of out_ (its size, past the text)
  int depth_ = 0;
  bool first_ = true;  ///< nothing written yet in the innermost open container
  bool after_key_ = false;
};

/// Gives the document to a nlohmann SAX handler.
class SaxSink {
 public:
  explicit SaxSink(JsonSax& handler) : h_(handler) {}

  void begin_object() { h_.start_object(kUnknownSize); }
  void end_object() { h_.end_object(); }
  void begin_array() { h_.start_array(kUnknownSize); }
  void end_array() { h_.end_array(); }
  void key(std::string_view k) {
    text_.assign(k);
    h_.key(text_);
  }
  void null() { h_.null(); }
  void boolean(bool b) { h_.boolean(b); }
  void pair(Vec2 v) {
    begin_array();
    number(v.x);
    number(v.y);
    end_array();
  }
  void number(double v) {
    if (std::isfinite(v)) {
      h_.number_float(v, kNoText);
    } else {
      h_.null();  // as in the text
    }
  }
  void integer(std::int64_t v) { h_.number_integer(v); }
  void unsigned_integer(std::uint64_t v) { h_.number_unsigned(v); }
  void string(std::string_view s) {
    text_.assign(s);
    h_.string(text_);
  }
  void other(const json&) { h_.null(); }
  template <class Emit>
  void array(std::size_t n, const Emit& emit) {
    begin_array();
    for (std::size_t i = 0; i < n; ++i) emit(*this, i);
    end_array();
  }

 private:
  static constexpr std::size_t kUnknownSize = static_cast<std::size_t>(-1);
  inline static const std::string kNoText;
  JsonSax& h_;
  std::string text_;
};

// ---------------------------------------------------------------- the fields, once

template <class Sink>
void emit_value(Sink& s, const json& v) {
  switch (v.type()) {
    case json::value_t::null:
      s.null();
      return;
    case json::value_t::boolean:
      s.boolean(v.get<bool>());
      return;
    case json::value_t::number_integer:
      s.integer(v.get<std::int64_t>());
      return;
    case json::value_t::number_unsigned:
      s.unsigned_integer(v.get<std::uint64_t>());
      return;
    case json::value_t::number_float:
      s.number(v.get<double>());
      return;
    case json::value_t::string:
      s.string(v.get_ref<const std::string&>());
      return;
    case json::value_t::array:
      s.begin_array();
      for (const json& item : v) emit_value(s, item);
      s.end_array();
      return;
    case json::value_t::object:
      s.begin_object();
      for (auto it = v.begin(); it != v.end(); ++it) {
        s.key(it.key());
        emit_value(s, it.value());
      }
      s.end_object();
      return;
    default:
      s.other(v);
      return;
  }
}

/// An object the method left null is written as {}.
template <class Sink>
void emit_object_or_empty(Sink& s, const json& v) {
  if (v.is_null()) {
    s.begin_object();
    s.end_object();
  } else {
    emit_value(s, v);
  }
}

template <class Sink>
void emit_point(Sink& s, Vec2 p) {
  s.pair(p);
}

template <class Sink>
void emit_optional(Sink& s, const std::optional<double>& v) {
  if (v) {
    s.number(*v);
  } else {
    s.null();
  }
}

template <class Sink>
void emit_report(Sink& s, const Report& r) {
  // Per-segment reports and intersections exist only at the full level (the only one with the
  // curvature-variation energy).
  const bool full = r.curvature_variation_energy.has_value() || !r.segments.empty();
  s.begin_object();
  s.key("bending_energy");
  emit_optional(s, r.bending_energy);
  s.key("curvature_variation_energy");
  emit_optional(s, r.curvature_variation_energy);
  s.key("energy_singular");
  s.boolean(r.energy_singular);
  if (full) {
    s.key("intersections");
    s.array(r.intersections.size(), [&](auto& to, std::size_t i) {
      const Intersection& x = r.intersections[i];
      to.begin_object();
      to.key("point");
      emit_point(to, x.point);
      to.key("segment_a");
      to.unsigned_integer(x.segment_a);
      to.key("segment_b");
      to.unsigned_integer(x.segment_b);
      to.key("u_a");
      to.number(x.u_a);
      to.key("u_b");
      to.number(x.u_b);
      to.end_object();
    });
  }
  s.key("length");
  emit_optional(s, r.length);
  s.key("linearized_energy");
  s.number(r.linearized_energy);
  s.key("max_curvature_jump");
  s.number(r.max_curvature_jump);
  s.key("max_interpolation_residual");
  s.number(r.max_interpolation_residual);
  s.key("max_tangent_angle_jump_deg");
  s.number(r.max_tangent_angle_jump_deg);
  s.key("min_relative_speed");
  s.number(r.min_relative_speed);
  s.key("regular");
  s.boolean(r.regular);
  if (full) {
    s.key("segment_reports");
    s.array(r.segments.size(), [&](auto& to, std::size_t i) {
      const SegmentReport& g = r.segments[i];
      to.begin_object();
      to.key("bending_energy");
      to.number(g.bending_energy);
      to.key("curvature_variation_energy");
      to.number(g.curvature_variation_energy);
      to.key("has_cusp");
      to.boolean(g.has_cusp);
      to.key("has_fold");
      to.boolean(g.has_fold);
      to.key("has_loop");
      to.boolean(g.has_loop);
      to.key("length");
      to.number(g.length);
      to.key("linearized_energy");
      to.number(g.linearized_energy);
      to.key("min_relative_speed");
      to.number(g.min_relative_speed);
      to.key("regular");
      to.boolean(g.regular);
      to.end_object();
    });
  }
  s.end_object();
}

template <class Sink>
void emit_solver(Sink& s, const SolverReport& r) {
  s.begin_object();
  s.key("active");
  s.begin_array();
  for (const std::size_t i : r.active) s.unsigned_integer(i);
  s.end_array();
  s.key("iterations");
  s.integer(r.iterations);
  s.key("residual");
  s.number(r.residual);
  s.key("status");
  s.string(solver_status_name(r.status));
  s.key("tolerance");
  s.number(r.tolerance);
  s.end_object();
}

/// The method's report with "solver" (when the result has one) in its place among the keys;
/// the result's solver replaces a "solver" member of the method's own.
template <class Sink>
void emit_method_report(Sink& s, const FitResult& r) {
  const json& m = r.method_report;
  if (!m.is_null() && !m.is_object()) {  // not a method's report; written as it is
    emit_value(s, m);
    return;
  }
  constexpr std::string_view kSolver = "solver";
  bool solver_written = !r.solver.has_value();
  const auto write_solver = [&] {
    s.key(kSolver);
    emit_solver(s, *r.solver);
    solver_written = true;
  };
  s.begin_object();
  if (m.is_object()) {
    for (auto it = m.begin(); it != m.end(); ++it) {
      const std::string& key = it.key();
      if (!solver_written && std::string_view(key) >= kSolver) {
        write_solver();
        if (key == kSolver) continue;
      }
      s.key(key);
      emit_value(s, it.value());
    }
  }
  if (!solver_written) write_solver();
  s.end_object();
}

/// Writes an object's keys in order, with the members of `extra` (an object or null) merged in
/// among them.
template <class Sink>
class Members {
 public:
  /// (`keep` is referred to, not copied: it must outlive this.)
  Members(Sink& s, const json& extra, const MemberFilter& keep)
      : s_(s), next_(members(extra).begin()), end_(members(extra).end()), keep_(keep) {}

  /// The key of the next member, if the filter keeps it (the caller then writes its value);
  /// the extra members before it are written first.
  template <std::size_t N>
  [[nodiscard]] bool key(const char (&key)[N]) {
    const std::string_view k(key, N - 1);
    flush([&](const std::string& e) { return std::string_view(e) < k; });
    if (next_ != end_ && std::string_view(next_.key()) == k) {
      throw Error(ErrorCode::kInvalidArgument,
                  "write_json: extra member '" + next_.key() + "' is a field of the result");
    }
    if (keep_ && !keep_(k)) return false;
    s_.key(key);
    return true;
  }

  /// The extra members after the last key.
  void finish() {
    flush([](const std::string&) { return true; });
  }

 private:
  /// `extra` itself, or an empty object for null (default iterators cannot be compared).
  static const json& members(const json& extra) {
    static const json kNone = json::object();
    if (extra.is_null()) return kNone;
    if (!extra.is_object()) {
      throw Error(ErrorCode::kInvalidArgument,
                  "write_json: extra members must be a JSON object, got " + extra.dump());
    }
    return extra;
  }

  template <class Before>
  void flush(Before before) {
    for (; next_ != end_ && before(next_.key()); ++next_) {
      s_.key(next_.key());
      emit_value(s_, next_.value());
    }
  }

  Sink& s_;
  json::const_iterator next_, end_;
  const MemberFilter& keep_;
};

/// input_to_json(in, accuracy) written: its points streamed in their place among the keys.
template <class Sink>
void emit_request(Sink& s, const FitInput& in, std::optional<double> accuracy) {
  constexpr std::string_view kPoints = "points";
  const json rest = detail::input_to_json_without_points(in, accuracy);
  bool points_written = in.points.empty();
  const auto write_points = [&] {
    s.key(kPoints);
    s.array(in.points.size(), [&](auto& to, std::size_t i) { emit_point(to, in.points[i]); });
    points_written = true;
  };
  s.begin_object();
  for (auto it = rest.begin(); it != rest.end(); ++it) {
    if (!points_written && std::string_view(it.key()) > kPoints) write_points();
    s.key(it.key());
    emit_value(s, it.value());
  }
  if (!points_written) write_points();
  s.end_object();
}

template <class Sink>
void emit_segments(Sink& s, const FitResult& r) {
  s.array(r.spline.segments.size(), [&](auto& to, std::size_t i) {
    const Segment& g = r.spline.segments[i];
    to.begin_object();
    to.key("bezier");
    to.begin_array();
    for (const Point& p : g.bezier.p) emit_point(to, p);
    to.end_array();
    to.key("span");
    to.unsigned_integer(g.span);
    to.key("t0");
    to.number(g.t0);
    to.key("t1");
    to.number(g.t1);
    to.end_object();
  });
}

template <class Sink>
void emit_result(Sink& s, const FitResult& r, const json& extra, const MemberFilter& keep = {}) {
  Members<Sink> m(s, extra, keep);
  s.begin_object();
  if (m.key("closed")) s.boolean(r.closed);
  if (m.key("knots")) {
    s.array(r.knots.size(), [&](auto& to, std::size_t i) { to.number(r.knots[i]); });
  }
  if (m.key("method")) s.string(r.method);
  if (m.key("method_report")) emit_method_report(s, r);
  if (m.key("options")) emit_object_or_empty(s, r.options);
  if (m.key("points")) {
    s.array(r.points.size(), [&](auto& to, std::size_t i) { emit_point(to, r.points[i]); });
  }
  if (r.report && m.key("report")) emit_report(s, *r.report);
  if (m.key("request")) emit_request(s, r.input, r.accuracy);
  if (m.key("segments")) emit_segments(s, r);
  if (m.key("tangents")) {
    s.array(r.tangents.size(), [&](auto& to, std::size_t i) { emit_point(to, r.tangents[i]); });
  }
  m.finish();
  s.end_object();
}

}  // namespace

/// At least the compact text of the result's long arrays (every number at its longest), so
/// that a long curve's text is not copied from doubling to doubling: only the pages written
/// are ever mapped in.
std::size_t text_bound(const FitResult& r) {
  constexpr std::size_t kNumber = 25;  // "-1.2345678901234567e-308" and a separator
  const std::size_t numbers = r.knots.size() +
                              2 * (r.points.size() + r.input.points.size() + r.tangents.size()) +
                              10 * r.spline.segments.size();
  return kNumber * numbers + 48 * r.spline.segments.size() + 4096;
}

void write_json(const FitResult& result, std::string& out, int indent, const json& extra,
                const MemberFilter& keep) {
  if (indent < 0) reserve_text(out, out.size(), out.size() + text_bound(result));
  TextSink sink(out, indent);
  emit_result(sink, result, extra, keep);
}

std::string write_json(const FitResult& result, int indent) {
  std::string out;
  write_json(result, out, indent);
  return out;
}

void write_json(const FitResult& result, std::ostream& out, int indent, const MemberFilter& keep) {
  std::string buffer;
  TextSink sink(buffer, indent, out);
  emit_result(sink, result, json(), keep);
  sink.flush();
}

void write_json(const FitResult& result, JsonSax& handler) {
  SaxSink sink(handler);
  emit_result(sink, result, json());
}

void write_json(const Report& report, JsonSax& handler) {
  SaxSink sink(handler);
  emit_report(sink, report);
}

void write_method_report(const FitResult& result, JsonSax& handler) {
  SaxSink sink(handler);
  emit_method_report(sink, result);
}

json to_json(const FitResult& result) {
  return json::parse(write_json(result));
}

json to_json(const Report& report) {
  std::string text;
  {
    TextSink sink(text, -1);  // cuts the text to its end when it goes
    emit_report(sink, report);
  }
  return json::parse(text);
}

}  // namespace fairspline::io
