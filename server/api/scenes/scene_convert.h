#pragma once
// Catalogue records -> wire messages.

#include "store/catalogue.h"
#include "vscan/v1/scene.pb.h"

namespace vscan::api {

void ToProto(const store::SceneRecord& scene, v1::Scene* out);
void ToProto(const store::ObjectRecord& object, v1::SceneObject* out);
void ToProto(const store::TableRecord& table, v1::RotaryTable* out);
void ToProto(const store::MeshRecord& mesh, v1::Mesh* out);

}  // namespace vscan::api
