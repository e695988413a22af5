// JsonQuote: every byte a JSON parser would refuse or misread is escaped, and nothing else changes.

#include "vscan/common/json_quote.h"

#include <gtest/gtest.h>

#include <string>

namespace vscan {
namespace {

TEST(JsonQuote, EscapesQuotesBackslashesAndControlCharacters) {
  EXPECT_EQ(JsonQuote(""), "\"\"");
  EXPECT_EQ(JsonQuote("bunny \"v2\"\\raw"), "\"bunny \\\"v2\\\"\\\\raw\"");
  EXPECT_EQ(JsonQuote("a\nb\rc\td"), "\"a\\nb\\rc\\td\"");
  EXPECT_EQ(JsonQuote(std::string("\x01\x1f", 2)), "\"\\u0001\\u001f\"");
  EXPECT_EQ(JsonQuote(std::string("nul\0byte", 8)), "\"nul\\u0000byte\"");
}

TEST(JsonQuote, KeepsUtf8AndEscapesTheScriptCloser) {
  EXPECT_EQ(JsonQuote("Müller ✓"), "\"Müller ✓\"");
  EXPECT_EQ(JsonQuote("</script>"), "\"\\u003c/script>\"");
}

}  // namespace
}  // namespace vscan
