#pragma once
// A minimal JSON writer for the reports jobs write: the caller opens and closes containers, the
// writer places commas. Non-finite numbers are written as null.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::service {

class JsonWriter {
 public:
  const std::string& str() const { return out_; }
  JsonWriter& Open(char bracket) {
    Separate();
    out_ += bracket;
    first_ = true;
    return *this;
  }
  JsonWriter& Close(char bracket) {
    out_ += bracket;
    first_ = false;
    return *this;
  }
  JsonWriter& Key(const std::string& key) {
    Separate();
    String(key);
    out_ += ':';
    first_ = true;
    return *this;
  }
  JsonWriter& Value(const std::string& text) {
    Separate();
    String(text);
    return *this;
  }
  JsonWriter& Value(const char* text) { return Value(std::string(text)); }
  JsonWriter& Value(double x) {
    Separate();
    if (!std::isfinite(x)) {
      out_ += "null";
      return *this;
    }
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.17g", x);
    out_ += buffer;
    return *this;
  }
  JsonWriter& Value(uint64_t x) {
    Separate();
    out_ += std::to_string(x);
    return *this;
  }
  JsonWriter& Value(bool b) {
    Separate();
    out_ += b ? "true" : "false";
    return *this;
  }
  JsonWriter& Array(const Eigen::VectorXd& v) {
    Open('[');
    for (Eigen::Index i = 0; i < v.size(); ++i) Value(v[i]);
    return Close(']');
  }
  JsonWriter& Vector(const Eigen::Vector3d& v) { return Open('[').Value(v.x()).Value(v.y()).Value(v.z()).Close(']'); }
  // Row-major 4x4, as the wire's Matrix4.
  JsonWriter& Matrix(const Pose3& pose) {
    Open('[');
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) Value(pose.matrix()(r, c));
    }
    return Close(']');
  }

 private:
  void Separate() {
    if (!first_) out_ += ',';
    first_ = false;
  }
  void String(const std::string& s) {
    out_ += '"';
    for (const char ch : s) {
      const auto c = static_cast<unsigned char>(ch);
      if (c == '"' || c == '\\') {
        out_ += '\\';
        out_ += ch;
      } else if (c < 0x20) {
        char buffer[8];
        std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
        out_ += buffer;
      } else {
        out_ += ch;
      }
    }
    out_ += '"';
  }

  std::string out_;
  bool first_ = true;
};

}  // namespace vscan::service
