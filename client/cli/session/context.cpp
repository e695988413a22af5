#include "session/context.h"

#include <cmath>
#include <cstdio>
#include <iostream>

#include <google/protobuf/util/json_util.h>

namespace vscan::cli {

client::Client* Context::GetClient() {
  if (client_) return &*client_;
  client::ClientOptions options;
  options.bearer_token = global.token;
  options.tls_root_cert_path = global.ca_cert;
  options.tls_client_cert_path = global.client_cert;
  options.tls_client_key_path = global.client_key;
  options.use_tls = global.tls;
  if (global.timeout) {
    // Rounded up, so that a deadline below a millisecond is still a deadline.
    const auto ms = std::chrono::milliseconds(static_cast<int64_t>(std::ceil(*global.timeout * 1000.0)));
    options.unary_timeout = ms;
    options.stream_timeout = ms;
  }
  auto connected = client::Client::Connect(global.server, options);
  if (!connected.ok()) {
    last_exit_ = connected.status().code() == StatusCode::kInvalidArgument ? UsageError(connected.status().message())
                                                                           : LocalError(connected.status());
    return nullptr;
  }
  client_.emplace(std::move(connected).value());
  return &*client_;
}

void Context::Say(const std::string& line) const {
  if (!global.json && !global.quiet) std::cout << line << std::endl;
}

void Context::Print(const std::string& line) const {
  if (!global.json) std::cout << line << std::endl;
}

void Context::Done(const std::string& line, const std::string& id) const {
  if (global.json) return;
  if (!global.quiet) {
    std::cout << line << std::endl;
  } else if (!id.empty()) {
    std::cout << id << std::endl;
  }
}

void Context::EmitJson(const std::string& json_object) const { std::cout << json_object << std::endl; }

int Context::ServerError(const Status& status) const {
  const bool unreachable =
      status.code() == StatusCode::kUnavailable || status.code() == StatusCode::kDeadlineExceeded;
  return Report(status, unreachable ? kExitUnreachable : kExitServerError);
}

int Context::LocalError(const Status& status) const {
  std::cerr << "error: " << status.message() << '\n';
  if (global.json) {
    EmitJson("{\"error\":{\"code\":\"LOCAL_IO\",\"message\":" + JsonQuote(status.message()) + "}}");
  }
  return kExitLocalIo;
}

int Context::UsageError(const std::string& message) const {
  std::cerr << "error: " << message << "\nRun with --help for more information.\n";
  return kExitUsage;
}

int Context::Report(const Status& status, int exit_code) const {
  const char* code = StatusCodeName(status.code());
  std::cerr << "error: " << code << ": " << status.message() << '\n';
  if (global.json) {
    EmitJson(std::string("{\"error\":{\"code\":") + JsonQuote(code) + ",\"message\":" + JsonQuote(status.message()) +
             "}}");
  }
  return exit_code;
}

std::string ToJson(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  std::string out;
  if (!google::protobuf::util::MessageToJsonString(message, &out, options).ok()) return "{}";
  return out;
}

}  // namespace vscan::cli
