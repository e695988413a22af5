#include "web/tls_front.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <openssl/err.h>
#include <openssl/ssl.h>

#include <atomic>
#include <cstring>
#include <condition_variable>
#include <mutex>
#include <system_error>
#include <thread>

#include <spdlog/spdlog.h>

namespace vscan::web {

struct TlsFront::State {
  TlsFrontOptions options;
  SSL_CTX* context = nullptr;
  int listener = -1;
  int stop_event = -1;  // readable once Stop was called
  int port = 0;
  std::thread acceptor;
  std::mutex mutex;
  std::condition_variable relays_done;
  int relays = 0;
  std::atomic<bool> stopping{false};

  ~State() {
    if (listener >= 0) close(listener);
    if (stop_event >= 0) close(stop_event);
    if (context) SSL_CTX_free(context);
  }
};

namespace {

std::string OpenSslError() {
  const unsigned long code = ERR_get_error();
  if (code == 0) return "unknown error";
  char text[256];
  ERR_error_string_n(code, text, sizeof(text));
  ERR_clear_error();
  return text;
}

void SetTimeouts(int fd, int milliseconds) {
  const timeval tv{milliseconds / 1000, (milliseconds % 1000) * 1000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
  setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof(tv));
}

bool SendAll(int fd, const char* data, size_t size) {
  while (size > 0) {
    const ssize_t n = send(fd, data, size, MSG_NOSIGNAL);
    if (n <= 0) return false;
    data += n;
    size -= static_cast<size_t>(n);
  }
  return true;
}

bool SslWriteAll(SSL* ssl, const char* data, size_t size) {
  while (size > 0) {
    const int n = SSL_write(ssl, data, static_cast<int>(size));
    if (n <= 0) return false;
    data += n;
    size -= static_cast<size_t>(n);
  }
  return true;
}

int ConnectBackend(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

// One client: the TLS handshake, then bytes both ways until either side closes, the connection idles
// past its limit, or the front stops.
void Relay(TlsFront::State& state, int client) {
  const TlsFrontOptions& options = state.options;
  SetTimeouts(client, options.handshake_timeout_ms);
  SSL* ssl = SSL_new(state.context);
  int backend = -1;
  if (ssl && SSL_set_fd(ssl, client) == 1 && SSL_accept(ssl) == 1 &&
      (backend = ConnectBackend(options.backend_port)) >= 0) {
    // civetweb's own 5 s waits bound the backend; a client that stops reading is cut off likewise.
    SetTimeouts(client, 5000);
    SetTimeouts(backend, 5000);
    char buffer[16384];
    pollfd fds[3] = {{client, POLLIN, 0}, {backend, POLLIN, 0}, {state.stop_event, POLLIN, 0}};
    while (!state.stopping.load()) {
      // Bytes OpenSSL already decrypted do not show on the socket.
      const int ready = SSL_pending(ssl) > 0 ? 1 : poll(fds, 3, options.idle_timeout_ms);
      if (ready <= 0 || (fds[2].revents & POLLIN)) break;
      if (SSL_pending(ssl) > 0 || (fds[0].revents & (POLLIN | POLLHUP | POLLERR))) {
        const int n = SSL_read(ssl, buffer, sizeof(buffer));
        if (n <= 0) {
          const int error = SSL_get_error(ssl, n);
          if (error == SSL_ERROR_WANT_READ || error == SSL_ERROR_WANT_WRITE) continue;
          break;
        }
        if (!SendAll(backend, buffer, static_cast<size_t>(n))) break;
      }
      if (fds[1].revents & (POLLIN | POLLHUP | POLLERR)) {
        const ssize_t n = recv(backend, buffer, sizeof(buffer), 0);
        if (n <= 0 || !SslWriteAll(ssl, buffer, static_cast<size_t>(n))) break;
      }
      fds[0].revents = fds[1].revents = fds[2].revents = 0;
    }
    SSL_shutdown(ssl);
  } else {
    ERR_clear_error();  // a failed handshake is the client's; nothing to report
  }
  if (backend >= 0) close(backend);
  if (ssl) SSL_free(ssl);
  close(client);
}

void Accept(std::shared_ptr<TlsFront::State> state) {
  pollfd fds[2] = {{state->listener, POLLIN, 0}, {state->stop_event, POLLIN, 0}};
  while (!state->stopping.load()) {
    if (poll(fds, 2, -1) <= 0) continue;
    if (fds[1].revents & POLLIN) break;
    const int client = accept4(state->listener, nullptr, nullptr, SOCK_CLOEXEC);
    if (client < 0) continue;
    {
      std::lock_guard lock(state->mutex);
      if (state->relays >= state->options.max_connections) {
        close(client);
        continue;
      }
      ++state->relays;
    }
    const auto done = [state] {
      std::lock_guard lock(state->mutex);
      if (--state->relays == 0) state->relays_done.notify_all();
    };
    try {
      std::thread([state, client, done] {
        Relay(*state, client);
        done();
      }).detach();
    } catch (const std::system_error&) {
      // No thread to be had: this client is turned away, as one past the limit is.
      close(client);
      done();
    }
  }
}

}  // namespace

StatusOr<std::unique_ptr<TlsFront>> TlsFront::Start(const TlsFrontOptions& options) {
  auto state = std::make_shared<State>();
  state->options = options;
  state->context = SSL_CTX_new(TLS_server_method());
  if (!state->context) return Unavailable("--tls-cert: cannot make a TLS context: " + OpenSslError());
  SSL_CTX_set_min_proto_version(state->context, TLS1_2_VERSION);
  if (SSL_CTX_use_certificate_chain_file(state->context, options.cert_file.c_str()) != 1) {
    return Unavailable("--tls-cert: '" + options.cert_file + "': " + OpenSslError());
  }
  if (SSL_CTX_use_PrivateKey_file(state->context, options.key_file.c_str(), SSL_FILETYPE_PEM) != 1 ||
      SSL_CTX_check_private_key(state->context) != 1) {
    return Unavailable("--tls-key: '" + options.key_file + "': " + OpenSslError());
  }
  if (!options.client_ca_file.empty()) {
    if (SSL_CTX_load_verify_locations(state->context, options.client_ca_file.c_str(), nullptr) != 1) {
      return Unavailable("--tls-client-ca: '" + options.client_ca_file + "': " + OpenSslError());
    }
    SSL_CTX_set_verify(state->context, SSL_VERIFY_PEER | SSL_VERIFY_FAIL_IF_NO_PEER_CERT, nullptr);
  }
  const size_t colon = options.address.rfind(':');
  sockaddr_in address{};
  address.sin_family = AF_INET;
  int port = -1;
  if (colon != std::string::npos) {
    try {
      port = std::stoi(options.address.substr(colon + 1));
    } catch (const std::exception&) {
      port = -1;
    }
  }
  if (colon == std::string::npos || port < 0 || port > 65535 ||
      inet_pton(AF_INET, options.address.substr(0, colon).c_str(), &address.sin_addr) != 1) {
    return Unavailable("--web-listen: '" + options.address + "' is not a numeric IPv4 HOST:PORT");
  }
  address.sin_port = htons(static_cast<uint16_t>(port));
  state->listener = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int yes = 1;
  setsockopt(state->listener, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  if (state->listener < 0 || bind(state->listener, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 ||
      listen(state->listener, 128) != 0) {
    return Unavailable("--web-listen: cannot listen on '" + options.address + "': " + std::strerror(errno));
  }
  socklen_t length = sizeof(address);
  getsockname(state->listener, reinterpret_cast<sockaddr*>(&address), &length);
  state->port = ntohs(address.sin_port);
  state->stop_event = eventfd(0, EFD_CLOEXEC);
  state->acceptor = std::thread(Accept, state);
  return std::unique_ptr<TlsFront>(new TlsFront(std::move(state)));
}

TlsFront::TlsFront(std::shared_ptr<State> state) : state_(std::move(state)) {}

TlsFront::~TlsFront() { Stop(); }

int TlsFront::port() const { return state_->port; }

void TlsFront::Stop() {
  if (state_->stopping.exchange(true)) return;
  const uint64_t one = 1;
  (void)!write(state_->stop_event, &one, sizeof(one));
  if (state_->acceptor.joinable()) state_->acceptor.join();
  std::unique_lock lock(state_->mutex);
  state_->relays_done.wait(lock, [&] { return state_->relays == 0; });
}

}  // namespace vscan::web
