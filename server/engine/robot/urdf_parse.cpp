#include "robot/urdf_parse.h"

#include <exception>
#include <mutex>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

namespace vscan::robot {
namespace {

constexpr size_t kMaxCapturedChars = 2000;

// urdfdom reports why a parse failed only through console_bridge; while a parse runs on this
// thread its error lines are collected here, everything else goes to the previous handler.
thread_local std::string* t_capture = nullptr;

class CapturingHandler final : public console_bridge::OutputHandler {
 public:
  explicit CapturingHandler(console_bridge::OutputHandler* previous) : previous_(previous) {}

  void log(const std::string& text, console_bridge::LogLevel level, const char* filename, int line) override {
    if (t_capture != nullptr) {
      if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && t_capture->size() < kMaxCapturedChars) {
        if (!t_capture->empty()) t_capture->append("; ");
        t_capture->append(text, 0, kMaxCapturedChars - t_capture->size());
      }
      return;
    }
    if (previous_ != nullptr) previous_->log(text, level, filename, line);
  }

 private:
  console_bridge::OutputHandler* previous_;
};

void InstallCapturingHandler() {
  static std::once_flag once;
  std::call_once(once, [] {
    static CapturingHandler handler(console_bridge::getOutputHandler());
    console_bridge::useOutputHandler(&handler);
  });
}

class CaptureScope {
 public:
  explicit CaptureScope(std::string* sink) { t_capture = sink; }
  ~CaptureScope() { t_capture = nullptr; }
  CaptureScope(const CaptureScope&) = delete;
  CaptureScope& operator=(const CaptureScope&) = delete;
};

// urdfdom links hold their children by shared_ptr, so the links of a URDF whose joints loop
// (refused later by CheckUrdfTree) would keep each other alive; the model's owner cuts those
// references before letting it go.
std::shared_ptr<const urdf::ModelInterface> Owned(urdf::ModelInterfaceSharedPtr model) {
  urdf::ModelInterface* raw = model.get();
  auto release = [model = std::move(model)](const urdf::ModelInterface*) mutable {
    for (auto& [name, link] : model->links_) {
      if (link == nullptr) continue;
      link->child_links.clear();
      link->child_joints.clear();
    }
    model.reset();
  };
  return std::shared_ptr<const urdf::ModelInterface>(raw, std::move(release));
}

}  // namespace

StatusOr<std::shared_ptr<const urdf::ModelInterface>> ParseUrdfXml(const std::string& xml) {
  InstallCapturingHandler();
  std::string errors;
  urdf::ModelInterfaceSharedPtr model;
  try {
    CaptureScope scope(&errors);
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    return InvalidArgument(std::string("urdf: ") + e.what());
  }
  if (model == nullptr) {
    return InvalidArgument("urdf: " + (errors.empty() ? std::string("not a valid URDF document") : errors));
  }
  return Owned(std::move(model));
}

}  // namespace vscan::robot
