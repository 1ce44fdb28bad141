#pragma once

/// @file CellIds.hpp
/// Ids of the cells of a build step by (start hit, end hit) (internal).

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace conftrack::detail {

/// Cell ids by (start hit, end hit) key: an open-addressing hash table
/// (linear probing, at most half full). The cells leaving a hit grow with
/// the hit density, so a list per start hit, searched linearly, made the
/// look-ups quadratic in it. Ids do not depend on the table's layout.
class CellIds {
 public:
  /// The id stored for `key`, or `id` stored for it now (second: true).
  std::pair<std::uint32_t, bool> insert(std::uint64_t key, std::size_t id) {
    if (2 * (m_size + 1) > m_keys.size()) {
      grow();
    }
    std::size_t i = slot(key);
    while (m_keys[i] != kEmpty) {
      if (m_keys[i] == key) {
        return {m_ids[i], false};
      }
      i = (i + 1) & (m_keys.size() - 1);
    }
    m_keys[i] = key;
    m_ids[i] = static_cast<std::uint32_t>(id);
    ++m_size;
    return {m_ids[i], true};
  }
  /// Forgets every entry and gives the memory back.
  void release() {
    std::vector<std::uint64_t>().swap(m_keys);
    std::vector<std::uint32_t>().swap(m_ids);
    m_size = 0;
  }

 private:
  static constexpr std::uint64_t kEmpty =
      std::numeric_limits<std::uint64_t>::max();
  std::size_t slot(std::uint64_t key) const {
    // Fibonacci hashing: the high bits of the product.
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> m_shift);
  }
  void grow() {
    std::vector<std::uint64_t> keys = std::move(m_keys);
    std::vector<std::uint32_t> ids = std::move(m_ids);
    const std::size_t capacity = keys.empty() ? 1024 : 2 * keys.size();
    m_shift = 64 - std::countr_zero(capacity);
    m_keys.assign(capacity, kEmpty);
    m_ids.assign(capacity, 0);
    m_size = 0;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (keys[i] != kEmpty) {
        insert(keys[i], ids[i]);
      }
    }
  }
  std::vector<std::uint64_t> m_keys;
  std::vector<std::uint32_t> m_ids;
  std::size_t m_size = 0;
  int m_shift = 64;
};

}  // namespace conftrack::detail
