// CTest fuzz.corpus.fuzz_fit: the committed inputs of fuzz_fit cannot silently change method.
//   fuzz_fit_check CORPUS_DIR DICT
// Every input names its method (the bytes before the first NUL, as fuzz_fit reads them with
// ByteReader::name): each file must name a registered method, except files whose name starts
// with "unknown-method", which must name one that is not registered (fuzz_fit's unknown-name
// path). Registering a method therefore changes no input, and renaming or removing one fails
// here instead of turning its inputs into unknown-name inputs. The libFuzzer dictionary DICT
// (fit.dict) must list exactly the registered names, each followed by the NUL that ends a name.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "fairspline/registry.hpp"
#include "fuzz_util.hpp"

namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A name for a message: printable ASCII as is, other bytes as \xNN.
std::string printable(const std::string& s) {
  std::string out;
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f && c != '\\') {
      out += c;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    }
  }
  return out;
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/// The values of a libFuzzer dictionary (lines `name="value"`, escapes \\, \" and \xNN; `#`
/// comments); false with a message on a line it cannot read.
bool read_dict(const fs::path& p, std::vector<std::string>& values) {
  std::ifstream in(p);
  if (!in) {
    std::fprintf(stderr, "fuzz_fit_check: cannot read %s\n", p.c_str());
    return false;
  }
  std::string line;
  for (int no = 1; std::getline(in, line); ++no) {
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::size_t open = line.find('"');
    const std::size_t close = line.rfind('"');
    if (open == std::string::npos || close <= open) {
      std::fprintf(stderr, "fuzz_fit_check: %s:%d: expected name=\"value\"\n", p.c_str(), no);
      return false;
    }
    std::string v;
    for (std::size_t i = open + 1; i < close; ++i) {
      if (line[i] != '\\') {
        v += line[i];
      } else if (i + 1 < close && (line[i + 1] == '\\' || line[i + 1] == '"')) {
        v += line[++i];
      } else if (i + 3 < close && line[i + 1] == 'x' && hex_digit(line[i + 2]) >= 0 &&
                 hex_digit(line[i + 3]) >= 0) {
        v += static_cast<char>(hex_digit(line[i + 2]) * 16 + hex_digit(line[i + 3]));
        i += 3;
      } else {
        std::fprintf(stderr, "fuzz_fit_check: %s:%d: bad escape\n", p.c_str(), no);
        return false;
      }
    }
    values.push_back(v);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: fuzz_fit_check CORPUS_DIR DICT\n");
    return 2;
  }
  std::set<std::string> registered;
  for (const fairspline::MethodInfo& m : fairspline::methods()) registered.insert(m.name);

  int bad = 0;
  std::map<std::string, int> per_method;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(argv[1])) {
    if (e.is_regular_file()) files.push_back(e.path());
  }
  if (files.empty()) {
    std::fprintf(stderr, "fuzz_fit_check: no inputs in %s\n", argv[1]);
    return 2;
  }
  for (const fs::path& f : files) {
    const std::string bytes = read_file(f);
    fairspline::fuzz::ByteReader in(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                    bytes.size());
    const std::string name = in.name(fairspline::fuzz::kMaxNameLength);
    const bool known = registered.count(name) != 0;
    const bool meant_unknown = f.filename().string().rfind("unknown-method", 0) == 0;
    if (known && !meant_unknown) {
      ++per_method[name];
    } else if (!known && meant_unknown) {
      ++per_method["(unknown-method inputs)"];
    } else if (known) {
      std::fprintf(stderr,
                   "fuzz_fit_check: %s names the registered method '%s', but its file name says "
                   "it is an unknown-method input; rename it or change the name in it\n",
                   f.c_str(), name.c_str());
      ++bad;
    } else {
      std::fprintf(stderr,
                   "fuzz_fit_check: %s names '%s', which is not a registered method (renamed or "
                   "removed? an input in the old format?). fuzz_fit would only check that the name "
                   "is refused; change the name in the file to the method it was written for "
                   "(docs/fuzzing.md), or call it unknown-method-* if that is what it tests\n",
                   f.c_str(), printable(name).c_str());
      ++bad;
    }
  }

  std::vector<std::string> dict;
  if (!read_dict(argv[2], dict)) return 1;
  std::set<std::string> dict_names;
  for (const std::string& v : dict) {
    if (!v.empty() && v.back() == '\0') dict_names.insert(v.substr(0, v.size() - 1));
  }
  for (const std::string& m : registered) {
    if (!dict_names.count(m)) {
      std::fprintf(stderr,
                   "fuzz_fit_check: %s lacks the registered method '%s' (as \"%s\\x00\"); "
                   "tests/fuzz/make_fit_seeds.py rewrites it\n",
                   argv[2], m.c_str(), m.c_str());
      ++bad;
    }
  }
  for (const std::string& m : dict_names) {
    if (!registered.count(m)) {
      std::fprintf(stderr,
                   "fuzz_fit_check: %s lists '%s', which is not a registered method; "
                   "tests/fuzz/make_fit_seeds.py rewrites it\n",
                   argv[2], printable(m).c_str());
      ++bad;
    }
  }

  for (const auto& [name, count] : per_method)
    std::printf("%-28s %d inputs\n", name.c_str(), count);
  if (bad) {
    std::fprintf(stderr, "fuzz_fit_check: %d problems\n", bad);
    return 1;
  }
  std::printf(
      "fuzz_fit_check: %zu inputs, each naming a registered method (or meant unknown); "
      "the dictionary lists the %zu registered methods\n",
      files.size(), registered.size());
  return 0;
}
