// SceneService.UploadMesh: collects the client stream, then imports on a worker thread.

#include <algorithm>
#include <cctype>
#include <string>

#include <spdlog/spdlog.h>

#include "api/scenes/material_convert.h"
#include "api/scenes/scene_convert.h"
#include "api/scenes/scene_service.h"
#include "api/transport/stored_enum_convert.h"
#include "api/transport/upload_reactor.h"
#include "api/transport/validate.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

geometry::MeshFileFormat FormatOf(const v1::MeshHeader& header) {
  switch (header.format()) {
    case v1::MESH_FORMAT_PLY: return geometry::MeshFileFormat::kPly;
    case v1::MESH_FORMAT_OBJ: return geometry::MeshFileFormat::kObj;
    case v1::MESH_FORMAT_STL: return geometry::MeshFileFormat::kStl;
    default: break;
  }
  std::string name = header.name();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  auto ends_with = [&](const char* ext) { return name.ends_with(ext); };
  if (ends_with(".ply")) return geometry::MeshFileFormat::kPly;
  if (ends_with(".obj")) return geometry::MeshFileFormat::kObj;
  if (ends_with(".stl")) return geometry::MeshFileFormat::kStl;
  return geometry::MeshFileFormat::kAuto;
}

class UploadMeshReactor final : public UploadReactor<v1::UploadMeshRequest> {
 public:
  UploadMeshReactor(grpc::CallbackServerContext* ctx, v1::UploadMeshResponse* response, service::ServiceContext& context)
      : UploadReactor(ctx, context, "UploadMesh"), response_(response) {
    Start();
  }

 private:
  Status Accept(const v1::UploadMeshRequest& request) override {
    if (request.has_header()) {
      if (has_header_) return InvalidArgument("header: sent twice; only the first message is a header");
      has_header_ = true;
      header_ = request.header();
      RETURN_IF_ERROR(CheckText(header_.name(), "header.name"));
      if (!v1::MeshFormat_IsValid(header_.format())) {
        return InvalidArgument("header.format: unknown value " + std::to_string(header_.format()));
      }
      if (header_.unit() == v1::LENGTH_UNIT_UNSPECIFIED) {
        return InvalidArgument("header.unit: required (the length unit the file is written in)");
      }
      if (MetresPerUnit(header_.unit()) == 0 || !kLengthUnits.Backward(header_.unit())) return InvalidArgument("header.unit: unknown unit");
      ASSIGN_OR_RETURN(scale_, ScaleOrDefault(header_.scale(), "header.scale"));
      ASSIGN_OR_RETURN(material_,
                       OptionalMaterialFromProto(header_.has_material(), header_.material(), "header.material"));
      if (header_.size_bytes() > context_.options.limits.max_upload_bytes) {
        return ResourceExhausted("header.size_bytes: " + std::to_string(header_.size_bytes()) +
                                 " bytes exceeds the upload limit of " +
                                 std::to_string(context_.options.limits.max_upload_bytes));
      }
      return Status::Ok();
    }
    if (!has_header_) return InvalidArgument("header: the first message must carry the header");
    if (bytes_.size() + request.chunk().size() > context_.options.limits.max_upload_bytes) {
      return ResourceExhausted("chunk: upload exceeds the limit of " +
                               std::to_string(context_.options.limits.max_upload_bytes) + " bytes");
    }
    bytes_ += request.chunk();
    return Status::Ok();
  }

  Status Complete() override {
    if (!has_header_) return InvalidArgument("header: the first message must carry the header");
    scenes::MeshUpload upload;
    upload.name = header_.name().empty() ? "mesh" : header_.name();
    upload.format = FormatOf(header_);
    upload.unit = *kLengthUnits.Backward(header_.unit());
    upload.metres_per_unit = MetresPerUnit(header_.unit());
    upload.scale = scale_;
    upload.material = material_;
    ASSIGN_OR_RETURN(store::MeshRecord mesh, context_.registry.AddMesh(bytes_, upload));
    ToProto(mesh, response_->mutable_mesh());
    return Status::Ok();
  }

  v1::UploadMeshResponse* response_;
  v1::MeshHeader header_;
  bool has_header_ = false;
  double scale_ = 1.0;
  std::optional<store::MaterialRecord> material_;
  std::string bytes_;
};

}  // namespace

grpc::ServerReadReactor<v1::UploadMeshRequest>* SceneService::UploadMesh(grpc::CallbackServerContext* ctx,
                                                                         v1::UploadMeshResponse* response) {
  return new UploadMeshReactor(ctx, response, context_);
}

}  // namespace vscan::api
