// vscan-poisson: reads the points, normals and options of one screened Poisson solve from stdin
// (reconstruction/poisson_process.h) and writes the mesh to stdout. vscand runs the solver here so
// that cancelling a job kills it at once; PCL's solver has no way to be interrupted.

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <iterator>
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

}  // namespace

int main() {
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
