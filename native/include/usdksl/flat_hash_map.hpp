#pragma once
/// @file flat_hash_map.hpp
/// @brief The hash map of the core's hot per-pair lookups.

#include "usdksl/huge_page_allocator.hpp"

#include <boost/unordered/unordered_flat_map.hpp>
#include <boost/unordered/unordered_flat_set.hpp>

#include <functional>
#include <utility>

namespace usdksl {

/// @brief Open-addressing hash map (Boost.Unordered's flat map). The kinetic
///        front's index and the tester's found pairs hold millions of keys on
///        a million-face cloth: a node-based std::unordered_map pays an
///        allocation per insert and a cache miss per node on every lookup
///        (the front index alone took 7% of that check's time in perf, and
///        free() 2% more). Nothing iterates these maps, so their
///        order cannot reach an answer. Large tables sit on huge pages.
template <class Key, class Value>
using FlatHashMap = boost::unordered_flat_map<Key, Value, boost::hash<Key>, std::equal_to<Key>,
                                              HugePageAllocator<std::pair<const Key, Value>>>;

/// @brief The set of the same kind (the pairs earlier time windows found).
template <class Key>
using FlatHashSet = boost::unordered_flat_set<Key, boost::hash<Key>, std::equal_to<Key>, HugePageAllocator<Key>>;

} // namespace usdksl
