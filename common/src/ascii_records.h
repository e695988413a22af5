#pragma once
// ASCII PLY and PCD bodies: whitespace-separated values, one per scalar of the record layout, turned
// into the binary records cloud_records decodes, so that both encodings read the same fields.
// Bounded by the text: a count that promises more values than the text can hold is refused before
// anything is allocated.

#include <cstddef>
#include <string>
#include <string_view>

#include "cloud_records.h"

namespace vscan::cloud_records {

class AsciiRecords {
 public:
  // `what` names the element in messages ("vertex", "points").
  AsciiRecords(std::string_view text, const RecordLayout& layout, std::string path, std::string what);

  // DATA_LOSS unless the text has room for `records` records of the layout (each value takes at
  // least one character and one separator), and for `values` loose values before them.
  Status CheckRoom(size_t records, size_t values = 0) const;
  // Steps over `values` values (PLY elements before the vertices).
  Status Skip(size_t values);
  // A RecordSource: parses the next `points` records into out.
  Status Fill(char* out, size_t first, size_t points);

 private:
  // The next value; empty at the end of the text.
  std::string_view Next();

  std::string_view text_;
  size_t at_ = 0;
  const RecordLayout& layout_;
  std::string path_, what_;
  size_t values_per_record_ = 0;
};

}  // namespace vscan::cloud_records
