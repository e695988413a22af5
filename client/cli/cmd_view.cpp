#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <string>

#include "session/commands.h"
#include "vscan/common/json_quote.h"

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

// The page's query parameter for a job of kind (as Job.kind names it).
std::string ViewOfJobKind(const std::string& kind) {
  if (kind == "bin_fill") return "bin";
  if (kind == "dataset") return "dataset";
  if (kind == "picking") return "picking";
  return "job";  // campaigns and model jobs
}

// Opens url in the desktop's browser, without waiting for it, when there is a display to show it on.
bool OpenInBrowser(const std::string& url) {
  if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY")) return false;
  const pid_t child = fork();
  if (child < 0) return false;
  if (child == 0) {
    // In a session of its own before we return (so that a closing terminal does not take it along),
    // and reparented to init by the exit below; the browser's chatter does not reach our output.
    setsid();
    if (fork() != 0) _exit(0);
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    execlp("xdg-open", "xdg-open", url.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  waitpid(child, &status, 0);
  return true;
}

}  // namespace

void AddViewCommand(CLI::App& app, Context& ctx) {
  auto* cmd = app.add_subcommand("view",
                                 "Print the address of the web view of a scene, job, stored cloud or the list of "
                                 "them (and open it when there is a display); vscand serves it with --web-listen");
  auto id = std::make_shared<std::string>();
  auto web = std::make_shared<std::string>();
  auto https = std::make_shared<bool>(false);
  auto no_open = std::make_shared<bool>(false);
  cmd->add_option("ID", *id, "A scene (scn_...), job (job_...) or stored cloud (cld_...) id (default: the lists)");
  cmd->add_option("--web", *web, "HOST:PORT of vscand's --web-listen")->envname("VSCAN_WEB");
  cmd->add_flag("--https", *https, "vscand serves the web view with TLS (--tls-cert)");
  cmd->add_flag("--no-open", *no_open, "Only print the address, even when there is a display");
  OnRun(cmd, ctx, [&ctx, id, web, https, no_open]() -> int {
    if (web->empty()) return ctx.UsageError("--web: give vscand's --web-listen address (HOST:PORT) or set VSCAN_WEB");
    if (!IsHostPort(*web)) return ctx.UsageError("--web: '" + *web + "' is not HOST:PORT");
    std::string url = (*https ? "https://" : "http://") + *web + "/";
    if (id->starts_with("scn_")) {
      url += "?scene=" + PercentEncode(*id);
    } else if (id->starts_with("cld_")) {
      url += "?cloud=" + PercentEncode(*id);
    } else if (id->starts_with("job_")) {
      // The job's kind says which view shows it; asking also checks that the job exists.
      auto* client = ctx.GetClient();
      if (!client) return ctx.last_exit();
      const auto job = client->GetJob(*id);
      if (!job.ok()) return ctx.ServerError(job.status());
      url += "?" + ViewOfJobKind(job->kind()) + "=" + PercentEncode(*id);
    } else if (!id->empty()) {
      return ctx.UsageError("ID: '" + *id + "' is not a scene (scn_), job (job_) or cloud (cld_) id");
    }
    // The token goes in the fragment, which browsers never send to the server or put in logs.
    if (!ctx.global.token.empty()) url += "#token=" + PercentEncode(ctx.global.token);
    const bool opened = !*no_open && isatty(STDOUT_FILENO) && OpenInBrowser(url);
    if (ctx.json()) {
      ctx.EmitJson("{\"url\":" + JsonQuote(url) + ",\"opened\":" + (opened ? "true" : "false") + "}");
    } else {
      ctx.Print(url);
    }
    return kExitOk;
  });
}

}  // namespace vscan::cli
