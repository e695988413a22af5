#include "service/bins/bin_fill_report.h"

namespace vscan::service {

const char* UnitName(store::LengthUnit unit) {
  switch (unit) {
    case store::LengthUnit::kMetre: return "m";
    case store::LengthUnit::kCentimetre: return "cm";
    case store::LengthUnit::kMillimetre: return "mm";
    case store::LengthUnit::kInch: return "in";
    case store::LengthUnit::kFoot: return "ft";
    case store::LengthUnit::kUnspecified: break;
  }
  return "";
}

}  // namespace vscan::service
