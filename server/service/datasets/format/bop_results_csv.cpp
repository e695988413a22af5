#include "service/datasets/format/bop_results_csv.h"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/LU>

#include "vscan/common/text_excerpt.h"

namespace vscan::service::dataset {
namespace {

constexpr std::string_view kHeader = "scene_id,im_id,obj_id,score,R,t,time";
constexpr std::array<std::string_view, 7> kColumns = {"scene_id", "im_id", "obj_id", "score", "R", "t", "time"};

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

class RowReader {
 public:
  RowReader(std::string_view field, size_t line) : field_(field), line_(line) {}

  Status Error(size_t column, std::string_view text) const {
    return InvalidArgument(std::string(field_), "line " + std::to_string(line_) + ", column " +
                                                    std::to_string(column + 1) + " (" +
                                                    std::string(kColumns[column]) + "): " + std::string(text));
  }

  StatusOr<uint32_t> Id(std::string_view text, size_t column) const {
    text = Trim(text);
    uint64_t value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() ||
        value > std::numeric_limits<uint32_t>::max()) {
      return Error(column, "'" + Excerpt(text) + "' is not a whole number from 0 to 4294967295");
    }
    return static_cast<uint32_t>(value);
  }

  // Space-separated finite numbers, exactly count of them.
  StatusOr<std::vector<double>> Numbers(std::string_view text, size_t column, size_t count) const {
    std::vector<double> values;
    size_t at = 0;
    while (true) {
      while (at < text.size() && (text[at] == ' ' || text[at] == '\t' || text[at] == '\r')) ++at;
      if (at == text.size()) break;
      size_t end = at;
      while (end < text.size() && text[end] != ' ' && text[end] != '\t' && text[end] != '\r') ++end;
      const std::string_view word = text.substr(at, end - at);
      if (values.size() == count) {
        return Error(column, "expected " + Count(count) + ", found more");
      }
      double value = 0;
      const auto [stop, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
      if (ec != std::errc() || stop != word.data() + word.size()) {
        return Error(column, "'" + Excerpt(word) + "' is not a number");
      }
      if (!std::isfinite(value)) return Error(column, "'" + Excerpt(word) + "' is not finite");
      values.push_back(value);
      at = end;
    }
    if (values.size() != count) {
      return Error(column, "expected " + Count(count) + ", found " + std::to_string(values.size()));
    }
    return values;
  }

 private:
  static std::string Count(size_t n) { return std::to_string(n) + (n == 1 ? " number" : " numbers"); }
  static std::string Excerpt(std::string_view text) { return TextExcerpt(text, 40); }

  std::string_view field_;
  size_t line_;
};

StatusOr<BopResultRow> ParseRow(std::string_view text, std::string_view field, size_t line) {
  const RowReader reader(field, line);
  std::array<std::string_view, 7> cells;
  size_t count = 0, at = 0;
  while (true) {
    const size_t comma = text.find(',', at);
    const std::string_view cell = text.substr(at, comma == std::string_view::npos ? std::string_view::npos : comma - at);
    if (count == cells.size()) {
      return InvalidArgument(std::string(field), "line " + std::to_string(line) +
                                                     ": more than 7 comma-separated fields (" +
                                                     std::string(kHeader) + ")");
    }
    cells[count++] = cell;
    if (comma == std::string_view::npos) break;
    at = comma + 1;
  }
  if (count != cells.size()) {
    return InvalidArgument(std::string(field), "line " + std::to_string(line) + ": " + std::to_string(count) +
                                                   " comma-separated fields, expected 7 (" + std::string(kHeader) +
                                                   ")");
  }
  BopResultRow row;
  row.line = line;
  ASSIGN_OR_RETURN(row.scene_id, reader.Id(cells[0], 0));
  ASSIGN_OR_RETURN(row.im_id, reader.Id(cells[1], 1));
  ASSIGN_OR_RETURN(row.obj_id, reader.Id(cells[2], 2));
  ASSIGN_OR_RETURN(const std::vector<double> score, reader.Numbers(cells[3], 3, 1));
  row.score = score[0];
  ASSIGN_OR_RETURN(const std::vector<double> r, reader.Numbers(cells[4], 4, 9));
  for (int i = 0; i < 9; ++i) row.camera_R_model(i / 3, i % 3) = r[static_cast<size_t>(i)];
  const double deviation = (row.camera_R_model.transpose() * row.camera_R_model - Eigen::Matrix3d::Identity())
                               .cwiseAbs()
                               .maxCoeff();
  if (!(deviation <= kMaxResultRotationDeviation) || !(row.camera_R_model.determinant() > 0)) {
    return reader.Error(4, "not a rotation (R^T R differs from the identity by " + std::to_string(deviation) +
                               ", determinant " + std::to_string(row.camera_R_model.determinant()) + ")");
  }
  ASSIGN_OR_RETURN(const std::vector<double> t, reader.Numbers(cells[5], 5, 3));
  row.camera_t_model_mm = Eigen::Vector3d(t[0], t[1], t[2]);
  if (!(row.camera_t_model_mm.cwiseAbs().maxCoeff() <= kMaxResultTranslationMm)) {
    return reader.Error(5, "beyond " + std::to_string(static_cast<int64_t>(kMaxResultTranslationMm)) +
                               " mm from the camera");
  }
  ASSIGN_OR_RETURN(const std::vector<double> time, reader.Numbers(cells[6], 6, 1));
  row.time = time[0];
  return row;
}

}  // namespace

StatusOr<std::vector<BopResultRow>> ParseBopResultsCsv(std::string_view text, std::string_view field) {
  std::vector<BopResultRow> rows;
  size_t line = 0, at = 0;
  bool first = true;
  while (at < text.size()) {
    size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view content = Trim(text.substr(at, end - at));
    at = end + 1;
    ++line;
    if (content.empty()) continue;
    const bool header = first && content == kHeader;
    first = false;
    if (header) continue;
    if (content.find('\0') != std::string_view::npos) {
      return InvalidArgument(std::string(field), "line " + std::to_string(line) + ": holds a NUL byte");
    }
    ASSIGN_OR_RETURN(BopResultRow row, ParseRow(content, field, line));
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace vscan::service::dataset
