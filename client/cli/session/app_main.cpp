#include "session/app_main.h"

#include <cmath>
#include <exception>
#include <iostream>

namespace vscan::cli {
namespace {

constexpr const char* kFooter = R"(
Exit codes:
  0  success
  2  usage error (bad or missing arguments)
  3  the server answered with an error
  4  the server is unreachable (UNAVAILABLE or DEADLINE_EXCEEDED)
  5  local I/O error (cannot read an input or write an output file)

Environment:
  VSCAN_SERVER  default for --server
  VSCAN_TOKEN   default for --token
  VSCAN_WEB     default for `vscan view --web`
  VSCAN_CA_CERT, VSCAN_CLIENT_CERT, VSCAN_CLIENT_KEY
                defaults for --ca-cert, --client-cert, --client-key)";

}  // namespace

void AddGlobalOptions(CLI::App& app, GlobalOptions& g) {
  app.add_option("--server", g.server, "Server address host:port")->envname("VSCAN_SERVER")->capture_default_str();
  app.add_option("--token", g.token, "Bearer token sent with every call")->envname("VSCAN_TOKEN");
  app.add_option("--ca-cert", g.ca_cert, "PEM file of the CA certificates to trust; turns TLS on")
      ->envname("VSCAN_CA_CERT")
      ->check(CLI::ExistingFile);
  auto* cert = app.add_option("--client-cert", g.client_cert, "PEM client certificate for mutual TLS; turns TLS on")
                   ->envname("VSCAN_CLIENT_CERT")
                   ->check(CLI::ExistingFile);
  auto* key = app.add_option("--client-key", g.client_key, "PEM private key of --client-cert")
                  ->envname("VSCAN_CLIENT_KEY")
                  ->check(CLI::ExistingFile);
  cert->needs(key);
  key->needs(cert);
  app.add_flag("--tls", g.tls, "TLS with the system's CA certificates (implied by --ca-cert and --client-cert)");
  app.add_flag("--json", g.json, "Machine-readable output: one JSON object per command on stdout");
  app.add_option("--timeout", g.timeout, "Deadline in seconds for each call (default: 30 s, none for scans)")
      ->check(CLI::Range(1e-6, 1e7));
  app.add_flag("-q,--quiet", g.quiet, "Print only ids and errors; no progress bar");
}

int ParseAndRun(CLI::App& app, Context& ctx, int argc, char** argv) {
  app.footer(kFooter);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with exit code 0; every real parse error is a usage error.
    const int rc = app.exit(e);
    return rc == 0 ? 0 : kExitUsage;
  }
  if (!ctx.action) return ctx.UsageError("no command given");
  // CLI11's range check lets NaN through (every comparison with it is false).
  if (ctx.global.timeout && !std::isfinite(*ctx.global.timeout)) {
    return ctx.UsageError("--timeout: must be a number of seconds in [1e-06, 1e7]");
  }
  try {
    return ctx.action();
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 1;
  }
}

}  // namespace vscan::cli
