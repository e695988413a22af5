#pragma once
// Follows next_page_token until the server says there is no more.

#include <string>
#include <vector>

#include "vscan/common/status.h"

namespace vscan::client {

// fetch(token) returns one page response; items(page) its repeated field.
template <typename Item, typename Fetch, typename Items>
StatusOr<std::vector<Item>> CollectPages(Fetch fetch, Items items) {
  std::vector<Item> out;
  std::string token;
  for (;;) {
    ASSIGN_OR_RETURN(auto page, fetch(token));
    for (const auto& item : items(page)) out.push_back(item);
    if (page.next_page_token().empty()) return out;
    if (page.next_page_token() == token) {
      return DataLoss("server repeated page token '" + token + "'");
    }
    token = page.next_page_token();
  }
}

}  // namespace vscan::client
