// Shared pieces of the mesh readers and writers (private to src/io*.cpp):
// error reporting, text and byte cursors that check every length, polygon
// fans, validation, number formatting and the per-format entry points.
#pragma once

#include <array>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/io.h"
#include "foldfill/mesh.h"

namespace foldfill::io_detail {

// Throws the Error subclass of `kind` (throw_error), "SOURCE: problem".
[[noreturn]] void fail(ErrorKind kind, const std::string& source, const std::string& problem);

// A short, printable, one-line excerpt of `text` for error messages.
std::string excerpt(std::string_view text);

// Throws BadFormat if a text format holds binary data (a NUL byte).
void require_text(std::string_view bytes, const std::string& source);

inline constexpr std::string_view kUtf8ByteOrderMark = "\xEF\xBB\xBF";

inline bool starts_with(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

// `bytes` without a leading UTF-8 byte order mark, which some editors write
// and which would otherwise glue onto the first word. Throws BadFormat for the
// byte order mark of UTF-16 or UTF-32 text, naming the encoding.
std::string_view skip_byte_order_mark(std::string_view bytes, const std::string& source);

// Throws BadFormat for classic Mac text: `text` has CR line ends and no LF.
// The readers count lines by LF, so such a file would read as one line.
void require_line_feeds(std::string_view text, const std::string& source);

// The text of a file in a text format (OBJ, OFF, ASCII STL): without its
// UTF-8 byte order mark, checked by require_text and require_line_feeds.
std::string_view text_content(std::string_view bytes, const std::string& source);

// "1 face", "3 faces": `count` and the noun for it.
inline std::string count_of(long long count, const char* one, const char* many) {
  return std::to_string(count) + " " + (count == 1 ? one : many);
}

// A parsed mesh with what the validation needs to point at a culprit.
struct ParsedMesh {
  Mesh mesh;
  std::vector<int> vertex_lines;      // line of each vertex in a text file, or empty
  std::vector<int> face_lines;        // line of each face in a text file, or empty
  bool obj_indices = false;           // messages add the file's own 1-based index (OBJ)
  std::vector<std::string> warnings;  // "SOURCE: what was dropped or mended"
};

// Checks finite coordinates, face (and OBJ attribute) indices in range and
// three distinct vertices per face; throws NonFiniteCoordinate or BadFace.
// Messages count vertices and faces from 0, as the mesh does, and add the line
// where the file gives it: "vertex 4 (line 6)", "line 9: face repeats vertex 3".
void validate_parsed(const ParsedMesh& parsed, const std::string& source);
void validate_mesh(const Mesh& mesh, const std::string& source);

// Appends the polygon `corners` (at least 3) as the fan (c0, ci, ci+1).
inline void append_fan(const std::vector<int>& corners, std::vector<Tri>& faces) {
  for (size_t i = 1; i + 1 < corners.size(); ++i) {
    faces.push_back({corners[0], corners[i], corners[i + 1]});
  }
}

// Throws BadFace through `input` (a cursor) for a polygon of fewer than 3 corners.
template <class Input>
void require_polygon(const Input& input, long long corner_count) {
  if (corner_count < 3) {
    input.fail(ErrorKind::BadFace, "face with " + count_of(corner_count, "vertex", "vertices") +
                                       " (at least 3 needed)");
  }
}

inline bool is_space(char c) { return c == ' ' || (c >= '\t' && c <= '\r'); }
inline bool is_blank(char c) { return is_space(c) && c != '\n'; }

// Reads whitespace-separated words and numbers from text, counting lines.
// With Separator::Blanks a token never crosses a line end (OBJ statements);
// otherwise line ends separate tokens too, and with HashComments so does a
// `#` comment up to its line end (OFF).
class TextCursor {
 public:
  enum class Separator { Blanks, Lines, HashComments };

  TextCursor(std::string_view text, const std::string& source, Separator separator,
             int first_line = 1)
      : pos_(text.data()),
        end_(text.data() + text.size()),
        source_(source),
        sep_(separator),
        line_(first_line) {}

  bool at_end() const { return pos_ == end_; }
  int line() const { return line_; }
  size_t remaining() const { return static_cast<size_t>(end_ - pos_); }
  std::string_view rest() const { return {pos_, remaining()}; }

  // Skips the separators of this cursor's kind.
  void skip_separators() {
    while (pos_ != end_) {
      if (*pos_ == '\n') {
        if (sep_ == Separator::Blanks) return;
        ++line_;
        ++pos_;
      } else if (is_space(*pos_)) {
        ++pos_;
      } else if (*pos_ == '#' && sep_ == Separator::HashComments) {
        skip_to_line_end();
      } else {
        return;
      }
    }
  }

  // True when only blanks are left on the current line.
  bool at_line_end() {
    while (pos_ != end_ && is_blank(*pos_)) ++pos_;
    return pos_ == end_ || *pos_ == '\n';
  }

  // Moves to the start of the next line.
  void next_line() {
    skip_to_line_end();
    if (pos_ != end_) {
      ++pos_;
      ++line_;
    }
  }

  // The next run of non-space characters (empty at a line end or the end).
  std::string_view next_word() {
    skip_separators();
    const char* start = pos_;
    while (pos_ != end_ && !is_space(*pos_)) ++pos_;
    return {start, static_cast<size_t>(pos_ - start)};
  }

  // Throws BadFormat unless the next word is `expected`.
  void expect_word(std::string_view expected) {
    std::string_view word = next_word();
    if (word != expected) {
      fail(ErrorKind::BadFormat, "expected '" + std::string(expected) + "', found " +
                                     (word.empty() ? "the end of the line" : excerpt(word)));
    }
  }

  // The next number, which must end at a separator. An integer written with a
  // fraction or an exponent ("1.5", "3e0") is refused as such.
  template <class Number>
  Number next_number() {
    skip_separators();
    const char* start = pos_;
    Number value = number_prefix<Number>();
    if (!at_token_end()) fail_not_a_number(start);
    return value;
  }

  // A number at the cursor, followed by anything (OBJ corners `a/b/c`).
  // Floating-point values beyond the type's range become +-inf (or 0 when too
  // small), so that validation reports them as non-finite coordinates.
  template <class Number>
  Number number_prefix() {
    const char* first = pos_;
    if (first != end_ && *first == '+' && first + 1 != end_ && first[1] != '-') ++first;
    Number value{};
    auto [last, error] = std::from_chars(first, end_, value);
    if constexpr (std::is_integral_v<Number>) {
      if (error == std::errc::invalid_argument ||
          (last != end_ && (*last == '.' || *last == 'e' || *last == 'E'))) {
        fail_if_not_integer(first);
      }
    }
    if (error == std::errc::invalid_argument) fail_not_a_number(pos_);
    if (error == std::errc::result_out_of_range) {
      if constexpr (std::is_floating_point_v<Number>) {
        value = parse_out_of_range<Number>(first, last);
      } else {
        fail(ErrorKind::BadFormat,
             "number " + excerpt({pos_, size_t(last - pos_)}) + " is out of range");
      }
    }
    pos_ = last;
    return value;
  }

  // Throws BadFormat unless `count` items of `tokens_per_item` tokens each
  // could fit in the rest of the text, so that a header's claimed count is
  // never trusted for an allocation.
  void require_items(long long count, int tokens_per_item, const char* items) const {
    const auto max_tokens = static_cast<long long>((remaining() + 1) / 2);
    if (count < 0 || count > INT_MAX || count * tokens_per_item > max_tokens) {
      fail(ErrorKind::BadFormat,
           "claims " + std::to_string(count) + " " + items + " but the file is too short for them");
    }
  }

  // The character at the cursor, or '\0' at the end.
  char peek() const { return pos_ != end_ ? *pos_ : '\0'; }
  void advance() { ++pos_; }
  // True at a separator or the end, where a token must stop.
  bool at_token_end() const { return pos_ == end_ || is_space(*pos_); }

  [[noreturn]] void fail(ErrorKind kind, const std::string& problem) const {
    io_detail::fail(kind, source_, "line " + std::to_string(line_) + ": " + problem);
  }

 private:
  void skip_to_line_end() {
    const void* newline = std::memchr(pos_, '\n', static_cast<size_t>(end_ - pos_));
    pos_ = newline ? static_cast<const char*>(newline) : end_;
  }

  [[noreturn]] void fail_not_a_number(const char* start) const {
    const char* word_end = start;
    while (word_end != end_ && !is_space(*word_end)) ++word_end;
    if (word_end == start) fail(ErrorKind::BadFormat, "expected a number");
    fail(ErrorKind::BadFormat,
         "expected a number, found " + excerpt({start, size_t(word_end - start)}));
  }

  // Throws BadFormat when the token at `first` (up to a separator or an OBJ
  // `/`) is a number but not an integer.
  void fail_if_not_integer(const char* first) const {
    const char* token_end = first;
    while (token_end != end_ && !is_space(*token_end) && *token_end != '/') ++token_end;
    double value;
    const auto [last, error] = std::from_chars(first, token_end, value);
    if (last == token_end && error != std::errc::invalid_argument) {
      fail(ErrorKind::BadFormat,
           "an integer is needed, found " + excerpt({pos_, size_t(token_end - pos_)}));
    }
  }

  // from_chars reports over- and underflow without a value; strtod gives it.
  template <class Float>
  static Float parse_out_of_range(const char* first, const char* last) {
    std::string text(first, last);
    if constexpr (std::is_same_v<Float, float>) return std::strtof(text.c_str(), nullptr);
    return std::strtod(text.c_str(), nullptr);
  }

  const char* pos_;
  const char* end_;
  const std::string& source_;
  Separator sep_;
  int line_;
};

inline constexpr bool kHostLittleEndian = __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__;

// `value` with its bytes in reverse order.
template <class T>
T byte_swapped(T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

// Reads binary scalars of one byte order, checking every length.
class ByteCursor {
 public:
  ByteCursor(std::string_view bytes, const std::string& source, bool little_endian)
      : pos_(bytes.data()),
        end_(bytes.data() + bytes.size()),
        source_(source),
        swap_(little_endian != kHostLittleEndian) {}

  size_t remaining() const { return static_cast<size_t>(end_ - pos_); }

  template <class T>
  T read() {
    require(sizeof(T));
    T value;
    std::memcpy(&value, pos_, sizeof(T));
    pos_ += sizeof(T);
    return swap_ ? byte_swapped(value) : value;
  }

  void skip(uint64_t byte_count) {
    require(byte_count);
    pos_ += byte_count;
  }

  // Throws BadFormat unless `byte_count` more bytes are there.
  void require(uint64_t byte_count) const {
    if (byte_count > remaining()) fail(ErrorKind::BadFormat, "file is truncated");
  }

  [[noreturn]] void fail(ErrorKind kind, const std::string& problem) const {
    io_detail::fail(kind, source_, problem);
  }

 private:
  const char* pos_;
  const char* end_;
  const std::string& source_;
  bool swap_;
};

// Appends `value` in little-endian byte order.
template <class T>
void append_little_endian(std::string& out, T value) {
  if (!kHostLittleEndian) value = byte_swapped(value);
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

// Appends the shortest text that reads back as exactly `value`.
template <class Number>
void append_number(std::string& out, Number value) {
  char text[32];
  auto result = std::to_chars(text, text + sizeof(text), value);
  out.append(text, result.ptr);
}

// Appends `values` separated by spaces, then a newline.
template <class Number, size_t N>
void append_numbers_line(std::string& out, const std::array<Number, N>& values) {
  for (size_t i = 0; i < N; ++i) {
    if (i) out += ' ';
    append_number(out, values[i]);
  }
  out += '\n';
}

// Where a serializer puts its bytes: a string that is either kept whole
// (serialize_mesh) or handed on in chunks of about kChunkBytes as it fills (a
// file being written), so that writing a large mesh does not hold its whole
// file in memory. Serializers append to bytes() and call record_done() after
// each record (a vertex, a face).
class ByteSink {
 public:
  using Consumer = std::function<void(std::string_view)>;
  static constexpr size_t kChunkBytes = size_t{1} << 20;

  ByteSink() = default;
  explicit ByteSink(Consumer consumer) : consumer_(std::move(consumer)) {}

  std::string& bytes() { return bytes_; }

  // Reserves room for the whole output when it is kept whole.
  void expect(size_t total_bytes) { bytes_.reserve(consumer_ ? kChunkBytes + 256 : total_bytes); }

  void record_done() {
    if (consumer_ && bytes_.size() >= kChunkBytes) hand_on();
  }

  // Hands on what is left; returns the whole output when it was kept whole.
  std::string finish() {
    if (consumer_) hand_on();
    return std::move(bytes_);
  }

 private:
  void hand_on() {
    consumer_(bytes_);
    bytes_.clear();
  }

  Consumer consumer_;
  std::string bytes_;
};

// The formats (one file each). Parsers leave validation to the caller;
// serializers expect a validated mesh.
ParsedMesh parse_obj(std::string_view bytes, const std::string& source);
ParsedMesh parse_ply(std::string_view bytes, const std::string& source);
ParsedMesh parse_off(std::string_view bytes, const std::string& source);
ParsedMesh parse_stl(std::string_view bytes, const std::string& source);
void serialize_obj(const Mesh& mesh, ByteSink& sink);
void serialize_ply(const Mesh& mesh, bool binary, ByteSink& sink);
void serialize_off(const Mesh& mesh, ByteSink& sink);
void serialize_stl(const Mesh& mesh, bool binary, ByteSink& sink);

}  // namespace foldfill::io_detail
