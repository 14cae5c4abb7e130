// The arch layer's data-dependent reads, reductions, permutes and narrow loads and stores against
// their contracts (kernels/arch_layer.hpp), stated as scalar code (tests/arch_layer/checks.hpp).
// Buffers are filled with a sentinel around the bytes a primitive may touch, so a store that
// writes too much, or a masked lane that is written, shows.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "kernels/codes.hpp"
#include "kernels/simd.hpp"
#include "tests/arch_layer/sets.hpp"
#include "tests/arch_layer/values.hpp"

namespace reproject::test {
namespace {

template <int L>
using Indices = std::array<std::int32_t, L>;

// Index vectors over [0, n): every column in every lane (broadcasts), the identity and its
// reverse where they fit, and random ones.
template <int L>
std::vector<Indices<L>> index_patterns(int n, std::mt19937& rng, int random_count) {
  std::vector<Indices<L>> patterns;
  Indices<L> x{};
  for (int c = 0; c < n; ++c) {
    x.fill(c);
    patterns.push_back(x);
  }
  if (n >= L) {
    for (int i = 0; i < L; ++i) x[i] = i;
    patterns.push_back(x);
    for (int i = 0; i < L; ++i) x[i] = n - 1 - i;
    patterns.push_back(x);
  }
  std::uniform_int_distribution<int> column(0, n - 1);
  for (int k = 0; k < random_count; ++k) {
    for (int i = 0; i < L; ++i) x[i] = column(rng);
    patterns.push_back(x);
  }
  return patterns;
}

inline std::uint32_t special_at(std::size_t k) { return special_values()[k % special_values().size()]; }

template <class Arch>
Outcome check_gather() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  const int n = 3 * L + 5;  // the row, in floats
  std::mt19937 rng(23);
  const auto patterns = index_patterns<L>(n, rng, 400);
  std::vector<std::uint8_t> storage(4 * n + 64);
  for (int offset = 0; offset < 4; ++offset) {  // the row at every byte alignment
    std::uint8_t* row = storage.data() + 16 + offset;
    for (int k = 0; k < n; ++k) {
      const std::uint32_t v = special_at(static_cast<std::size_t>(7 * k + offset));
      std::memcpy(row + 4 * k, &v, 4);
    }
    const float* base = reinterpret_cast<const float*>(row);
    for (const Indices<L>& index : patterns) {
      std::uint32_t got[L];
      V::bits(detail::gather<Arch>(base, V::ints(index.data())), got);
      for (int i = 0; i < L; ++i) {
        std::uint32_t want;
        std::memcpy(&want, row + 4 * index[i], 4);
        ++out.lanes;
        if (got[i] != want) {
          out.fail(lane_text(i) + "gather(row at byte offset " + std::to_string(offset) + ", index " + std::to_string(index[i]) +
                   ") = " + show(got[i]) + ", contract " + show(want));
        }
      }
    }
  }
  return out;
}

template <class Arch>
Outcome check_index_for_gather() {
  Outcome out;
  using V = Vec<Arch>;
  std::mt19937 rng(29);
  for (const Indices<V::L>& index : index_patterns<V::L>(4 * V::L, rng, 100)) {
    detail::LaneIndex<Arch> lanes;
    detail::index_for_gather(lanes, V::ints(index.data()));
    std::int32_t got[V::L];
    V::ints_out(lanes.index, got);
    for (int i = 0; i < V::L; ++i) {
      ++out.lanes;
      if (got[i] != index[i]) out.fail(lane_text(i) + "index_for_gather kept " + std::to_string(got[i]) + " for " + std::to_string(index[i]));
    }
  }
  return out;
}

// IEEE totalOrder as a signed integer key.
inline std::int32_t total_order(std::uint32_t bits) {
  std::int32_t i;
  std::memcpy(&i, &bits, 4);
  return i ^ ((i >> 31) & 0x7fffffff);
}

template <class Arch>
Outcome check_lane_extreme() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  auto check = [&](const std::uint32_t* lanes) {
    std::uint32_t least = lanes[0], greatest = lanes[0];
    for (int i = 1; i < L; ++i) {
      if (total_order(lanes[i]) < total_order(least)) least = lanes[i];
      if (total_order(lanes[i]) > total_order(greatest)) greatest = lanes[i];
    }
    const std::pair<std::uint32_t, std::uint32_t> got{bits_of_value(detail::lane_extreme<Arch, false>(V::floats(lanes))),
                          bits_of_value(detail::lane_extreme<Arch, true>(V::floats(lanes)))};
    out.lanes += L;
    std::string all;
    for (int i = 0; i < L; ++i) all += (i ? ", " : "") + show(lanes[i]);
    if (got.first != least) out.fail("lane_extreme<min>(" + all + ") = " + show(got.first) + ", contract " + show(least));
    if (got.second != greatest) out.fail("lane_extreme<max>(" + all + ") = " + show(got.second) + ", contract " + show(greatest));
  };
  const std::vector<std::uint32_t>& specials = special_values();
  std::uint32_t lanes[L];
  for (std::uint32_t filler : specials) {  // one value in every lane position among copies of another
    for (std::uint32_t odd : specials) {
      for (int p = 0; p < L; ++p) {
        for (int i = 0; i < L; ++i) lanes[i] = i == p ? odd : filler;
        check(lanes);
      }
    }
  }
  std::mt19937 rng(31);
  std::uniform_int_distribution<std::size_t> pick(0, specials.size() - 1);
  for (int k = 0; k < 20000; ++k) {
    for (int i = 0; i < L; ++i) lanes[i] = specials[pick(rng)];
    check(lanes);
  }
  return out;
}

template <class Arch>
Outcome no_permute() {
  Outcome out;
  out.not_applicable = "no variable permute on this set (has_permute is false): the column fetch gathers";
  return out;
}

template <class Arch>
Outcome check_first_lane() {
  if constexpr (!detail::has_permute<Arch>()) {
    return no_permute<Arch>();
  } else {
    Outcome out;
    using V = Vec<Arch>;
    std::uint32_t lanes[V::L];
    for (std::size_t k = 0; k < special_values().size(); ++k) {
      for (int i = 0; i < V::L; ++i) lanes[i] = special_at(k + 3 * static_cast<std::size_t>(i));
      const std::uint32_t got = bits_of_value(detail::first_lane<Arch>(V::floats(lanes)));
      ++out.lanes;
      if (got != lanes[0]) out.fail("first_lane of a vector whose lane 0 is " + show(lanes[0]) + " = " + show(got));
    }
    return out;
  }
}

template <class Arch, bool TwoRegisters>
Outcome check_permutes() {
  if constexpr (!detail::has_permute<Arch>()) {
    return no_permute<Arch>();
  } else {
    Outcome out;
    using V = Vec<Arch>;
    constexpr int L = V::L;
    constexpr int kSources = TwoRegisters ? 2 * L : L;
    std::mt19937 rng(TwoRegisters ? 41 : 37);
    const char* name = TwoRegisters ? "permute_two_registers" : "permute";
    for (int round = 0; round < 8; ++round) {
      std::uint32_t source[2 * L];
      for (int i = 0; i < 2 * L; ++i) source[i] = special_at(static_cast<std::size_t>(round * 11 + 5 * i));
      for (const Indices<L>& index : index_patterns<L>(kSources, rng, 200)) {
        detail::LaneIndex<Arch> lanes;
        std::uint32_t got[L];
        if constexpr (TwoRegisters) {
          detail::index_for_two_registers(lanes, V::ints(index.data()));
          V::bits(detail::permute_two_registers<Arch>(V::floats(source), V::floats(source + L), lanes), got);
        } else {
          detail::index_for_permute(lanes, V::ints(index.data()));
          V::bits(detail::permute<Arch>(V::floats(source), lanes), got);
        }
        for (int i = 0; i < L; ++i) {
          ++out.lanes;
          if (got[i] != source[index[i]]) {
            out.fail(lane_text(i) + name + " with index " + std::to_string(index[i]) + " = " + show(got[i]) + ", contract " +
                     show(source[index[i]]));
          }
        }
      }
    }
    return out;
  }
}

constexpr std::uint32_t kSentinel = 0x5e5e0000u;  // + the float's position: every float differs

template <class Arch>
Outcome check_store_first_lanes() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  std::vector<int> counts;
  for (int c = 0; c <= L + 2; ++c) counts.push_back(c);
  counts.insert(counts.end(), {2 * L, 1000});
  for (int count : counts) {
    for (int round = 0; round < 4; ++round) {
      std::uint32_t value[L], buffer[3 * L];
      for (int i = 0; i < L; ++i) value[i] = special_at(static_cast<std::size_t>(round * 13 + i));
      for (int k = 0; k < 3 * L; ++k) buffer[k] = kSentinel + static_cast<std::uint32_t>(k);
      float* at = reinterpret_cast<float*>(buffer) + L;
      detail::store_first_lanes<Arch>(V::floats(value), at, count);
      for (int k = 0; k < 3 * L; ++k) {
        const int lane = k - L;
        const bool written = lane >= 0 && lane < L && lane < count;
        const std::uint32_t want = written ? value[lane] : kSentinel + static_cast<std::uint32_t>(k);
        ++out.lanes;
        if (buffer[k] != want) {
          out.fail("store_first_lanes(count " + std::to_string(count) + "): float " + std::to_string(lane) +
                   " from the store's start is " + show(buffer[k]) + ", contract " + show(want));
        }
      }
    }
  }
  return out;
}

template <class Arch>
Outcome check_store_bytes() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  for (int start = 0; start < 256; ++start) {
    std::uint32_t value[L];
    std::uint8_t buffer[3 * L];
    for (int i = 0; i < L; ++i) value[i] = bits_of_value(static_cast<float>((start + 37 * i) % 256));
    for (int k = 0; k < 3 * L; ++k) buffer[k] = static_cast<std::uint8_t>(0xa5 ^ k);
    detail::store_bytes<Arch>(V::floats(value), buffer + L);
    for (int k = 0; k < 3 * L; ++k) {
      const int lane = k - L;
      const std::uint8_t want = lane >= 0 && lane < L ? static_cast<std::uint8_t>(value_of_bits(value[lane]))
                                                      : static_cast<std::uint8_t>(0xa5 ^ k);
      ++out.lanes;
      if (buffer[k] != want) {
        out.fail("store_bytes: byte " + std::to_string(lane) + " from the store's start is " + std::to_string(buffer[k]) +
                 ", contract " + std::to_string(want));
      }
    }
  }
  return out;
}

inline std::vector<std::uint16_t> u16_codes() {
  std::vector<std::uint16_t> codes = {0, 1, 2, 0x00ff, 0x0100, 0x7fff, 0x8000, 0x8001, 0xfffe, 0xffff, 0x1234, 0xabcd};
  std::mt19937 rng(43);
  for (int k = 0; k < 500; ++k) codes.push_back(static_cast<std::uint16_t>(rng()));
  return codes;
}

template <class Arch>
Outcome check_load_u16() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  const std::vector<std::uint16_t> codes = u16_codes();
  std::uint8_t buffer[2 * L + 8];
  for (int offset = 0; offset < 4; ++offset) {
    for (std::size_t first = 0; first < codes.size(); ++first) {
      for (int i = 0; i < L; ++i) detail::store_u16_at(buffer + offset + 2 * i, codes[(first + i) % codes.size()]);
      std::int32_t got[L];
      V::ints_out(detail::load_u16<Arch>(buffer + offset), got);
      for (int i = 0; i < L; ++i) {
        const std::int32_t want = codes[(first + i) % codes.size()];
        ++out.lanes;
        if (got[i] != want) {
          out.fail(lane_text(i) + "load_u16 at byte offset " + std::to_string(offset) + " = " + std::to_string(got[i]) +
                   ", contract " + std::to_string(want));
        }
      }
    }
  }
  return out;
}

template <class Arch>
Outcome check_store_u16() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  const std::vector<std::uint16_t> codes = u16_codes();
  // Write masks: none, all, every single lane, every lane but one, alternating, random.
  std::vector<std::array<bool, L>> masks;
  std::array<bool, L> m{};
  masks.push_back(m);
  m.fill(true);
  masks.push_back(m);
  for (int p = 0; p < L; ++p) {
    for (int i = 0; i < L; ++i) m[i] = i == p;
    masks.push_back(m);
    for (int i = 0; i < L; ++i) m[i] = i != p;
    masks.push_back(m);
  }
  for (int i = 0; i < L; ++i) m[i] = i % 2 == 0;
  masks.push_back(m);
  std::mt19937 rng(47);
  for (int k = 0; k < 64; ++k) {
    for (int i = 0; i < L; ++i) m[i] = rng() % 2 == 0;
    masks.push_back(m);
  }
  std::uint8_t buffer[4 * L + 8];
  int round = 0;
  for (const auto& write : masks) {
    for (bool masked : {false, true}) {
      for (int offset = 0; offset < 2; ++offset) {
        ++round;
        std::int32_t lanes[L];
        for (int i = 0; i < L; ++i) lanes[i] = codes[static_cast<std::size_t>(round * 7 + i) % codes.size()];
        for (std::size_t k = 0; k < sizeof buffer; ++k) buffer[k] = static_cast<std::uint8_t>(0x3c + 5 * k);
        std::uint8_t* at = buffer + L + offset;
        detail::store_u16<Arch>(V::ints(lanes), V::mask(write.data()), masked, at);
        for (std::size_t k = 0; k < sizeof buffer; ++k) {
          const std::ptrdiff_t byte = buffer + k - at;
          std::uint8_t want = static_cast<std::uint8_t>(0x3c + 5 * k);
          if (byte >= 0 && byte < 2 * L && (!masked || write[byte / 2])) {
            want = static_cast<std::uint8_t>(lanes[byte / 2] >> (8 * (byte % 2)));
          }
          ++out.lanes;
          if (buffer[k] != want) {
            out.fail("store_u16(" + std::string(masked ? "masked" : "every lane") + "): byte " + std::to_string(byte) +
                     " from the store's start is " + std::to_string(buffer[k]) + ", contract " + std::to_string(want));
          }
        }
      }
    }
  }
  return out;
}

}  // namespace
}  // namespace reproject::test
