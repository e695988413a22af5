#pragma once
// Untrusted bytes quoted in an error message: printable ASCII as it is, anything else (NUL,
// control characters, non-ASCII) as \xNN, cut to a bounded length.

#include <cstddef>
#include <string>
#include <string_view>

namespace vscan {

// At most max_bytes of input, then "..." when more followed.
std::string TextExcerpt(std::string_view bytes, size_t max_bytes = 60);

}  // namespace vscan
