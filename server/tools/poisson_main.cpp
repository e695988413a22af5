// vscan-poisson: reads the points, normals and options of one screened Poisson solve from stdin
// (reconstruction/poisson_process.h) and writes the mesh to stdout. vscand runs the solver here so
// that cancelling a job kills it at once; PCL's solver has no way to be interrupted.

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <iterator>
#include <new>
#include <string>

#include "reconstruction/poisson_process.h"

namespace {

bool WriteAll(const std::string& bytes) {
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(STDOUT_FILENO, bytes.data() + written, bytes.size() - written);
    if (n <= 0) return false;
    written += static_cast<size_t>(n);
  }
  return true;
}

// A failed allocation in any thread (the solver's own included) ends the helper with the status
// vscand reads as "past the memory bound"; any other uncaught exception aborts.
[[noreturn]] void OnTerminate() {
  if (std::exception_ptr error = std::current_exception()) {
    try {
      std::rethrow_exception(error);
    } catch (const std::bad_alloc&) {
      ::_exit(vscan::reconstruction::kPoissonOutOfMemoryExit);
    } catch (...) {
    }
  }
  std::abort();
}

}  // namespace

int main() {
  std::set_new_handler([] { ::_exit(vscan::reconstruction::kPoissonOutOfMemoryExit); });
  std::set_terminate(OnTerminate);
  std::ios::sync_with_stdio(false);
  const std::string bytes((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
  auto input = vscan::reconstruction::DecodePoissonInput(bytes);
  if (!input.ok()) {
    std::fprintf(stderr, "%s\n", input.status().message().c_str());
    return 2;
  }
  auto mesh = vscan::reconstruction::PoissonPcl(input->points, input->normals, input->options);
  if (!mesh.ok()) {
    std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
    return 3;
  }
  return WriteAll(vscan::reconstruction::EncodePoissonResult(*mesh)) ? 0 : 4;
}
