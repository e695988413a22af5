#pragma once
// A string as a JSON string literal, for the few JSON texts written by hand (the CLI's --json
// summaries, the web view's API).

#include <string>
#include <string_view>

namespace vscan {

// The text in double quotes with ", \ and the control characters escaped, and '<' as \u003c so that
// no text can close a script element if the JSON is ever inlined in a page. Bytes are copied as they
// are otherwise (UTF-8 passes through).
std::string JsonQuote(std::string_view text);

}  // namespace vscan
