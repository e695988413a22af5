#include "vscan/gl/egl_context.h"

#include <array>
#include <string_view>
#include <utility>
#include <vector>

#include <EGL/egl.h>
#include <EGL/eglext.h>

namespace vscan::gl {

struct EglContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  EGLSurface surface = EGL_NO_SURFACE;  // a 1x1 pbuffer, only where surfaceless contexts are missing
  std::string platform;
};

namespace {

struct Candidate {
  std::string name;
  EGLDisplay display = EGL_NO_DISPLAY;
};

std::string ErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    default: return "EGL error " + std::to_string(error);
  }
}

bool HasExtension(const char* list, std::string_view name) {
  if (list == nullptr) return false;
  const std::string_view all(list);
  for (size_t at = all.find(name); at != std::string_view::npos; at = all.find(name, at + 1)) {
    const bool starts = at == 0 || all[at - 1] == ' ';
    const size_t end = at + name.size();
    if (starts && (end == all.size() || all[end] == ' ')) return true;
  }
  return false;
}

std::vector<Candidate> Candidates() {
  std::vector<Candidate> out;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  const auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  const bool surfaceless = get_platform_display != nullptr && HasExtension(client, "EGL_MESA_platform_surfaceless");
  out.push_back({"surfaceless Mesa", surfaceless ? get_platform_display(EGL_PLATFORM_SURFACELESS_MESA,
                                                                         EGL_DEFAULT_DISPLAY, nullptr)
                                                 : EGL_NO_DISPLAY});
  const auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  if (get_platform_display != nullptr && query_devices != nullptr && HasExtension(client, "EGL_EXT_platform_device")) {
    std::array<EGLDeviceEXT, 16> devices{};
    EGLint count = 0;
    if (query_devices(static_cast<EGLint>(devices.size()), devices.data(), &count) == EGL_TRUE) {
      for (EGLint i = 0; i < count; ++i) {
        out.push_back({"EGL device " + std::to_string(i),
                       get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[static_cast<size_t>(i)], nullptr)});
      }
    }
  }
  out.push_back({"default display", eglGetDisplay(EGL_DEFAULT_DISPLAY)});
  // Clears an error left by a platform this EGL does not know.
  eglGetError();
  return out;
}

EGLContext CreateCoreContext(EGLDisplay display, EGLConfig config) {
  for (const auto& [major, minor] : {std::pair{4, 5}, std::pair{3, 3}}) {
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, major, EGL_CONTEXT_MINOR_VERSION, minor,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
    if (context != EGL_NO_CONTEXT) return context;
  }
  return EGL_NO_CONTEXT;
}

// Creates a core context on an initialised display and makes it current; the error when it cannot.
Status MakeContext(EglContext::Impl& impl) {
  const char* extensions = eglQueryString(impl.display, EGL_EXTENSIONS);
  const bool surfaceless = HasExtension(extensions, "EGL_KHR_surfaceless_context");
  const bool configless = HasExtension(extensions, "EGL_KHR_no_config_context");
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) return Unavailable("desktop OpenGL not supported");

  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!surfaceless || !configless) {
    const EGLint wanted[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint count = 0;
    if (eglChooseConfig(impl.display, wanted, &config, 1, &count) != EGL_TRUE || count == 0) {
      return Unavailable("no OpenGL pbuffer config");
    }
  }
  impl.context = CreateCoreContext(impl.display, config);
  if (impl.context == EGL_NO_CONTEXT) {
    return Unavailable("no OpenGL 3.3+ core context (" + ErrorName(eglGetError()) + ")");
  }
  if (!surfaceless) {
    const EGLint size[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
    impl.surface = eglCreatePbufferSurface(impl.display, config, size);
    if (impl.surface == EGL_NO_SURFACE) return Unavailable("cannot create a pbuffer (" + ErrorName(eglGetError()) + ")");
  }
  if (eglMakeCurrent(impl.display, impl.surface, impl.surface, impl.context) != EGL_TRUE) {
    return Unavailable("cannot make the context current (" + ErrorName(eglGetError()) + ")");
  }
  return Status::Ok();
}

// The display stays initialised: EGL hands every renderer of the process the same display, and
// terminating it would pull it from under the others.
void Destroy(EglContext::Impl& impl) {
  if (impl.display == EGL_NO_DISPLAY) return;
  eglMakeCurrent(impl.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (impl.surface != EGL_NO_SURFACE) eglDestroySurface(impl.display, impl.surface);
  if (impl.context != EGL_NO_CONTEXT) eglDestroyContext(impl.display, impl.context);
  impl = EglContext::Impl{};
}

}  // namespace

EglContext::EglContext(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

EglContext::~EglContext() {
  Destroy(*impl_);
  eglReleaseThread();
}

const std::string& EglContext::platform() const { return impl_->platform; }

StatusOr<std::unique_ptr<EglContext>> EglContext::CreateCurrent() {
  std::string tried;
  bool any_display = false;
  for (const Candidate& candidate : Candidates()) {
    if (!tried.empty()) tried += "; ";
    tried += candidate.name + ": ";
    if (candidate.display == EGL_NO_DISPLAY) {
      tried += "not available";
      continue;
    }
    EGLint major = 0, minor = 0;
    if (eglInitialize(candidate.display, &major, &minor) != EGL_TRUE) {
      tried += ErrorName(eglGetError());
      continue;
    }
    any_display = true;
    auto impl = std::make_unique<Impl>();
    impl->display = candidate.display;
    const Status made = MakeContext(*impl);
    if (made.ok()) {
      impl->platform = candidate.name + ", EGL " + std::to_string(major) + "." + std::to_string(minor);
      return std::unique_ptr<EglContext>(new EglContext(std::move(impl)));
    }
    tried += made.message();
    Destroy(*impl);
  }
  return Unavailable(std::string(any_display ? "no usable OpenGL context (" : "no EGL display (") + tried + ")");
}

}  // namespace vscan::gl
