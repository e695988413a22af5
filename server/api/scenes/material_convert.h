#pragma once
// Material messages <-> catalogue records, with the checks every request that carries one gets.

#include <optional>
#include <string_view>

#include "store/catalogue.h"
#include "vscan/common/status.h"
#include "vscan/v1/scene.pb.h"

namespace vscan::api {

// A present message must be a known preset or four values in range (roughness in (0, 1]), not
// both; INVALID_ARGUMENT naming "<field>.preset" or "<field>.values.<member>" otherwise.
StatusOr<store::MaterialRecord> MaterialFromProto(const v1::Material& material, std::string_view field);
// nullopt when the message is absent (has is false).
StatusOr<std::optional<store::MaterialRecord>> OptionalMaterialFromProto(bool has, const v1::Material& material,
                                                                          std::string_view field);
void ToProto(const store::MaterialRecord& material, v1::Material* out);

}  // namespace vscan::api
