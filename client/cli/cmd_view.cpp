#include <cctype>
#include <string>

#include "session/commands.h"

namespace vscan::cli {
namespace {

// RFC 3986 unreserved characters stay; everything else is percent-encoded.
std::string PercentEncode(const std::string& text) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (const unsigned char c : text) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

bool IsHostPort(const std::string& address) {
  if (address.empty() || address.find(':') == std::string::npos) return false;
  for (const unsigned char c : address) {
    if (!std::isalnum(c) && c != '.' && c != '-' && c != ':' && c != '[' && c != ']') return false;
  }
  return true;
}

}  // namespace

void AddViewCommand(CLI::App& app, Context& ctx) {
  auto* cmd = app.add_subcommand(
      "view", "Print the address of the web view of a scene (or of the scene list); vscand serves it with --web-listen");
  auto scene = std::make_shared<std::string>();
  auto web = std::make_shared<std::string>();
  cmd->add_option("scene", *scene, "Scene id (default: the list of scenes)");
  cmd->add_option("--web", *web, "HOST:PORT of vscand's --web-listen")->envname("VSCAN_WEB");
  OnRun(cmd, ctx, [&ctx, scene, web]() -> int {
    if (web->empty()) return ctx.UsageError("--web: give vscand's --web-listen address (HOST:PORT) or set VSCAN_WEB");
    if (!IsHostPort(*web)) return ctx.UsageError("--web: '" + *web + "' is not HOST:PORT");
    // The token goes in the fragment, which browsers never send to the server or put in logs.
    std::string url = "http://" + *web + "/";
    if (!scene->empty()) url += "?scene=" + PercentEncode(*scene);
    if (!ctx.global.token.empty()) url += "#token=" + PercentEncode(ctx.global.token);
    if (ctx.json()) {
      ctx.EmitJson("{\"url\":\"" + url + "\"}");
    } else {
      ctx.Print(url);
    }
    return kExitOk;
  });
}

}  // namespace vscan::cli
