#include "raster/frame_render.h"

#include <cmath>
#include <numbers>

#include "vscan/gl/gl_check.h"

namespace vscan::raster {
namespace {

bool Reversed(DepthFormat format) { return format == DepthFormat::kFloat32Reversed; }

Eigen::Matrix4f ClipFromScene(const RenderState& state, const FrameRequest& r) {
  const Eigen::Matrix4d clip_from_sensor = ClipFromSensor(*r.camera, r.planes.near, r.planes.far,
                                                          Reversed(r.depth_format), state.caps.clip_control);
  const Pose3 sensor_from_scene = r.world_from_sensor.inverse() * Eigen::Translation3d(r.scene_centre);
  return (clip_from_sensor * sensor_from_scene.matrix()).cast<float>();
}

Eigen::Vector3f Eye(const FrameRequest& r) {
  return (r.world_from_sensor.translation() - r.scene_centre).cast<float>();
}

// The direct term's uniforms and textures: the emitter moved from the sensor frame to the scene
// frame, face normals on unit 0, the scan's materials on unit 1.
Status SetDirectLight(RenderState& state, const GpuScene& scene, const FrameRequest& r, const LightUniforms& u) {
  const DirectLight& light = *r.direct_light;
  RETURN_IF_ERROR(state.materials.Upload(light, scene.slot_instance_ids()));
  const Eigen::Vector3f eye = Eye(r);
  glUniform3f(u.eye, eye.x(), eye.y(), eye.z());
  const Eigen::Vector3f position =
      (r.world_from_sensor * light.emitter.position - r.scene_centre).cast<float>();
  const Eigen::Vector3f axis = (r.world_from_sensor.linear() * light.emitter.axis.normalized()).cast<float>();
  glUniform3f(u.emitter_position, position.x(), position.y(), position.z());
  glUniform3f(u.emitter_axis, axis.x(), axis.y(), axis.z());
  // A full sphere has no cone test (the CPU skips it too), whatever the float rounding of l.axis.
  const double cone = light.emitter.cone_half_angle_rad;
  const float cos_cone = cone < std::numbers::pi ? static_cast<float>(std::cos(cone)) : -2.0f;
  glUniform2f(u.emitter, static_cast<float>(light.emitter.radiant_intensity_w_per_sr), cos_cone);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_BUFFER, scene.face_normal_texture());
  glUniform1i(u.face_normals, 0);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_BUFFER, state.materials.texture());
  glUniform1i(u.materials, 1);
  glActiveTexture(GL_TEXTURE0);
  return Status::Ok();
}

void UseColourProgram(const RenderState& state, const GpuScene& scene, const FrameRequest& r,
                      const Eigen::Matrix4f& clip_from_scene) {
  const ColourProgram& p = r.direct_light ? state.programs.lit_colour : state.programs.colour;
  const sensor::Lighting& light = r.camera->lighting;
  glUseProgram(p.id);
  glUniformMatrix4fv(p.clip_from_scene, 1, GL_FALSE, clip_from_scene.data());
  const Eigen::Vector3f eye = Eye(r);
  glUniform3f(p.eye, eye.x(), eye.y(), eye.z());
  glUniform2f(p.range_code, static_cast<float>(r.planes.near_range),
              static_cast<float>(65535.0 / (r.planes.far_range - r.planes.near_range)));
  // R holds intensity / max_intensity, where max_intensity = power / Attenuation(near_range).
  const double scale = light.power > 0 ? Attenuation(light, r.planes.near_range) : 0.0;
  glUniform4f(p.light, static_cast<float>(light.constant), static_cast<float>(light.linear),
              static_cast<float>(light.quadratic), static_cast<float>(scale));
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_BUFFER, scene.face_normal_texture());
  glUniform1i(p.face_normals, 0);
}

Status ReadBack(const FrameRequest& r, RenderedFrame& out) {
  const auto w = static_cast<GLsizei>(out.width), h = static_cast<GLsizei>(out.height);
  const size_t pixels = size_t{out.width} * out.height;
  out.faces.reset(new uint32_t[pixels]);
  glReadBuffer(kFaceAttachment);
  glReadPixels(0, 0, w, h, GL_RED_INTEGER, GL_UNSIGNED_INT, out.faces.get());
  if (r.method == RasterMethod::kDepthBuffer) {
    out.depth.reset(new uint32_t[pixels]);
    glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, r.depth_format == DepthFormat::kFixed24 ? GL_UNSIGNED_INT : GL_FLOAT,
                 out.depth.get());
  } else {
    out.colour.reset(new uint8_t[4 * pixels]);
    glReadBuffer(kColourAttachment);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, out.colour.get());
  }
  out.radiance.reset();
  if (r.direct_light != nullptr) {
    out.radiance.reset(new float[pixels]);
    glReadBuffer(kRadianceAttachment);
    glReadPixels(0, 0, w, h, GL_RED, GL_FLOAT, out.radiance.get());
  }
  return gl::CheckGl("raster: reading back the frame");
}

}  // namespace

Status RenderFrame(RenderState& state, const GpuScene& scene, const FrameRequest& r, RenderedFrame& out) {
  const bool colour = r.method == RasterMethod::kColourBuffer;
  const bool lit = r.direct_light != nullptr;
  RETURN_IF_ERROR(state.target.Prepare(r.camera->width, r.camera->height, r.depth_format, colour, lit));
  out.width = r.camera->width;
  out.height = r.camera->height;
  glViewport(0, 0, static_cast<GLsizei>(out.width), static_cast<GLsizei>(out.height));

  const bool reversed = Reversed(r.depth_format);
  glDepthFunc(reversed ? GL_GREATER : GL_LESS);
  const GLuint no_face[4] = {0, 0, 0, 0};
  const GLfloat black[4] = {0, 0, 0, 0};
  const GLfloat clear_depth = reversed ? 0.0f : 1.0f;
  glClearBufferuiv(GL_COLOR, 0, no_face);
  if (colour) glClearBufferfv(GL_COLOR, 1, black);
  if (lit) glClearBufferfv(GL_COLOR, 2, black);
  glClearBufferfv(GL_DEPTH, 0, &clear_depth);

  const Eigen::Matrix4f clip_from_scene = ClipFromScene(state, r);
  if (colour) {
    UseColourProgram(state, scene, r, clip_from_scene);
    if (lit) RETURN_IF_ERROR(SetDirectLight(state, scene, r, state.programs.lit_colour.direct));
  } else {
    const DepthProgram& p = lit ? state.programs.lit_depth : state.programs.depth;
    glUseProgram(p.id);
    glUniformMatrix4fv(p.clip_from_scene, 1, GL_FALSE, clip_from_scene.data());
    if (lit) RETURN_IF_ERROR(SetDirectLight(state, scene, r, p.direct));
  }
  scene.Draw();
  RETURN_IF_ERROR(gl::CheckGl("raster: drawing the scene"));
  return ReadBack(r, out);
}

}  // namespace vscan::raster
