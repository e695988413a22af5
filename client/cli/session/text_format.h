#pragma once
// Small text helpers the commands share for numbers and file names.

#include <string>

namespace vscan::cli {

// value with exactly `digits` decimals ("%.*f").
std::string Fixed(double value, int digits);
// value through a printf format with one double conversion, e.g. "%.3g".
std::string Format(const char* format, double value);
// text with ASCII letters lower-cased.
std::string Lower(std::string text);
// The extension of path, lower-cased, with its dot (".ply"); empty when it has none.
std::string LowerExtension(const std::string& path);

}  // namespace vscan::cli
