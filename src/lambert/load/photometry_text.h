#pragma once
// The text of photometric files, shared by the IES LM-63 reader (load/ies.cpp) and the EULUMDAT
// reader (load/eulumdat.cpp): lines with any line ending, whitespace- and comma-separated values
// with their line numbers, numbers read off them with file:line messages, and the symmetries by
// which a file's C planes cover the whole circle. Internal to load/.
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "lambert/light/photometry.h"

namespace lambert::photometry_text {

// Limits a file may not exceed: beyond them it is garbled, not large (real files have at most a
// few hundred angles per axis).
constexpr std::size_t kMaxAngles = 3600;

// s without its leading and trailing white space; s in upper case (ASCII).
std::string trim(const std::string& s);
std::string upper(std::string s);

// Lines of a text file with either line ending (\n, \r\n, or a lone \r).
std::vector<std::string> splitLines(const std::string& text);

// A number, the whole of `s`; false when it is not one (or not finite).
bool parseNumber(const std::string& s, double& out);

struct Token {
  std::string text;
  int line = 0;  // 1-based
};

// The whitespace- and comma-separated values of lines[first..], each with its line number (IES
// values may be split over lines anywhere, LM-63-2002 §5.10).
std::vector<Token> tokens(const std::vector<std::string>& lines, std::size_t first);

// Reads numbers off a token stream, failing with file:line and what was expected.
class NumberReader {
 public:
  NumberReader(const std::vector<Token>& tokens, std::string path, int lastLine)
      : tokens_(tokens), path_(std::move(path)), lastLine_(lastLine) {}
  bool next(const std::string& what, double& out) {
    if (at_ >= tokens_.size()) {
      error_ = path_ + ":" + std::to_string(lastLine_) + ": the file ends before " + what +
               " (it is truncated: get the complete file from its source)";
      return false;
    }
    const Token& t = tokens_[at_];
    if (!parseNumber(t.text, out)) {
      error_ = path_ + ":" + std::to_string(t.line) + ": expected a number for " + what + ", found \"" + t.text.substr(0, 40) +
               "\" (the file is damaged or not an IES LM-63 file)";
      return false;
    }
    line_ = t.line;
    ++at_;
    return true;
  }
  bool nextCount(const std::string& what, std::size_t min, std::size_t max, std::size_t& out) {
    double v = 0;
    if (!next(what, v)) return false;
    if (v != std::floor(v) || v < static_cast<double>(min) || v > static_cast<double>(max)) {
      error_ = path_ + ":" + std::to_string(line_) + ": " + what + " must be a whole number from " + std::to_string(min) +
               " to " + std::to_string(max) + ", found " + tokens_[at_ - 1].text;
      return false;
    }
    out = static_cast<std::size_t>(v);
    return true;
  }
  const std::string& error() const { return error_; }
  int line() const { return line_; }
  std::size_t remaining() const { return tokens_.size() - at_; }
  int nextLine() const { return at_ < tokens_.size() ? tokens_[at_].line : lastLine_; }

 private:
  const std::vector<Token>& tokens_;
  std::string path_;
  int lastLine_;
  std::size_t at_ = 0;
  int line_ = 0;
  std::string error_;
};

// How a file's horizontal angles cover the C planes (LM-63-2002 §5.13; EULUMDAT Isym).
enum class Symmetry { Rotational, Quadrant, BilateralC0, BilateralC90, Full };

// The full set of C planes from the planes a file gives: each given plane mirrored as the symmetry
// says, reduced to [0, 360), sorted, and the duplicates (0 and 360, a mirror plane onto itself)
// dropped. Returns the columns' source indices beside their angles.
void expandSymmetry(Symmetry symmetry, const std::vector<double>& given, const std::vector<double>& columns, std::size_t nV,
                    Photometry& out);

// Angles must rise; equal neighbours are a typing slip the reader cannot resolve.
std::string checkAscending(const std::vector<double>& angles, double lo, double hi, const std::string& what);

}  // namespace lambert::photometry_text
