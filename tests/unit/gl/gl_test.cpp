#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "vscan/gl/egl_context.h"
#include "vscan/gl/gl_api.h"
#include "vscan/gl/gl_check.h"
#include "vscan/gl/gl_program.h"
#include "vscan/gl/mesh_buffers.h"

namespace vscan::gl {
namespace {

constexpr const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
void main() {
  gl_Position = vec4(position, 1.0);
  gl_PointSize = 1.0;
}
)";

constexpr const char* kFragment = R"(#version 330 core
out vec4 fragment;
void main() { fragment = vec4(1.0, 0.0, 0.0, 1.0); }
)";

constexpr GLsizei kSide = 8;

// A context current on the test's thread and an 8x8 RGBA8 framebuffer bound for drawing.
class GlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto context = EglContext::CreateCurrent();
    ASSERT_TRUE(context.ok()) << context.status().message();
    context_ = std::move(*context);
    glGenRenderbuffers(1, &colour_);
    glBindRenderbuffer(GL_RENDERBUFFER, colour_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, kSide, kSide);
    glGenFramebuffers(1, &framebuffer_);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
    glViewport(0, 0, kSide, kSide);
    ASSERT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
    ASSERT_TRUE(CheckGl("set up").ok());
  }

  void TearDown() override {
    if (!context_) return;
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteRenderbuffers(1, &colour_);
  }

  // How many pixels the draw turned red.
  static int RedPixels() {
    std::vector<uint8_t> rgba(size_t{kSide} * kSide * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, kSide, kSide, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    int red = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) red += rgba[i] == 255 && rgba[i + 1] == 0;
    return red;
  }

  std::unique_ptr<EglContext> context_;
  GLuint framebuffer_ = 0, colour_ = 0;
};

TEST_F(GlTest, ContextIsCoreProfileAndNamesItsDisplay) {
  EXPECT_FALSE(context_->platform().empty());
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  EXPECT_GE(major * 10 + minor, 33);
}

TEST_F(GlTest, CheckGlDrainsTheErrorQueueAndNamesTheStep) {
  glEnable(0xFFFF);  // not a capability: GL_INVALID_ENUM
  glEnable(0xFFFF);
  const Status error = CheckGl("test: enabling");
  EXPECT_EQ(error.code(), StatusCode::kInternal);
  EXPECT_EQ(error.message(), "test: enabling: GL_INVALID_ENUM");
  EXPECT_TRUE(CheckGl("test: after").ok());
}

TEST_F(GlTest, BuildProgramReportsTheShaderThatDoesNotCompile) {
  const auto program = BuildProgram(kVertex, "#version 330 core\nvoid main() { undeclared = 1; }\n", "broken");
  ASSERT_FALSE(program.ok());
  EXPECT_EQ(program.status().code(), StatusCode::kInternal);
  EXPECT_EQ(program.status().message().rfind("broken fragment shader does not compile", 0), 0u)
      << program.status().message();
}

TEST_F(GlTest, MeshBuffersDrawTrianglesAndPoints) {
  const auto program = BuildProgram(kVertex, kFragment, "solid");
  ASSERT_TRUE(program.ok()) << program.status().message();
  glUseProgram(*program);
  // The left half of clip space as two triangles; the first vertex doubles as a point.
  const std::vector<Eigen::Vector3f> corners = {{-1, -1, 0}, {0, -1, 0}, {0, 1, 0}, {-1, 1, 0}};
  const std::vector<std::array<uint32_t, 3>> triangles = {{0, 1, 2}, {0, 2, 3}};
  {
    MeshBuffers mesh;
    mesh.AddAttribute(0, corners);
    mesh.SetTriangles(triangles);
    EXPECT_EQ(mesh.vertex_count(), 4u);
    EXPECT_EQ(mesh.triangle_count(), 2u);
    EXPECT_EQ(mesh.bytes(), 4u * 12 + 2u * 12);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    mesh.DrawTriangles();
    ASSERT_TRUE(CheckGl("test: triangles").ok());
    EXPECT_EQ(RedPixels(), kSide * kSide / 2);
  }
  {
    // Pixel centres, so that each point lands on exactly one pixel.
    const float step = 2.0f / kSide;
    const std::vector<Eigen::Vector3f> centres = {{-1 + step / 2, -1 + step / 2, 0}, {1 - step / 2, 1 - step / 2, 0}};
    MeshBuffers points;
    points.AddAttribute(0, centres);
    EXPECT_EQ(points.triangle_count(), 0u);
    glClear(GL_COLOR_BUFFER_BIT);
    points.DrawTriangles();  // none: nothing drawn
    points.DrawPoints();
    ASSERT_TRUE(CheckGl("test: points").ok());
    EXPECT_EQ(RedPixels(), 2);
  }
  glDeleteProgram(*program);
  EXPECT_TRUE(CheckGl("test: cleanup").ok());
}

}  // namespace
}  // namespace vscan::gl
