// partc/particle_set.hpp: ParticleSet<D, Vars...>, a structure-of-arrays particle
// container: positions, ids, alive flags and one contiguous std::vector per
// variable tag (struct P_v { using type = Vec<2>; static constexpr const char* name = "v"; }).
// A tag's type is what the set stores: Vec<2, float> or float for a variable
// the schedule stores as float. BasicParticleSet<Position, Vars...> chooses the
// positions' type too (Vec<2, float>); ParticleSet<D, ...> stores them as Vec<D>.
//
// Surprises:
// - bool variables are stored as std::uint8_t (storage_t<bool>), never as
//   std::vector<bool>, so every variable is a plain contiguous array.
// - An index is a position in the arrays and changes under erase_dead/permute;
//   the id is the particle's identity: assigned from next_id(), never reused.
// - for_each_variable visits "p" (positions) and the tagged variables, not id/alive.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "partc/parallel.hpp"
#include "partc/vec.hpp"

namespace partc {

template <class T>
struct Storage {
  using type = T;
};
template <>
struct Storage<bool> {
  using type = std::uint8_t;
};
template <class T>
using storage_t = typename Storage<T>::type;

template <class Position, class... Vars>
class BasicParticleSet {
 public:
  static constexpr int dim = Position::dim;
  using position_type = Position;

  std::size_t size() const { return positions_.size(); }
  bool empty() const { return positions_.empty(); }

  // What one particle takes in the arrays: position, id, alive flag and
  // every variable, as stored (partc --explain says the same number).
  static constexpr std::size_t bytes_per_particle =
      sizeof(Position) + sizeof(std::int64_t) + sizeof(std::uint8_t) +
      (std::size_t{0} + ... + sizeof(storage_t<typename Vars::type>));

  void reserve(std::size_t n) {
    for_each_array([n](auto& a) { a.reserve(n); });
  }

  // Returns the index of the new particle; its id is next_id().
  std::size_t push_back(const Position& position) { return append(position, next_id_++); }

  // For loading particles with given ids; duplicate ids are the caller's check.
  void push_back_with_id(const Position& position, std::int64_t id) {
    append(position, id);
    if (id >= next_id_) next_id_ = id + 1;
  }

  // Keeps next_id so that ids stay unique over the whole run.
  void clear() {
    for_each_array([](auto& a) { a.clear(); });
  }

  std::vector<Position>& positions() { return positions_; }
  const std::vector<Position>& positions() const { return positions_; }
  const std::vector<std::int64_t>& ids() const { return ids_; }
  std::vector<std::uint8_t>& alive() { return alive_; }
  const std::vector<std::uint8_t>& alive() const { return alive_; }

  template <class Var>
  std::vector<storage_t<typename Var::type>>& get() {
    return std::get<index_of<Var>()>(vars_);
  }
  template <class Var>
  const std::vector<storage_t<typename Var::type>>& get() const {
    return std::get<index_of<Var>()>(vars_);
  }

  std::int64_t next_id() const { return next_id_; }
  void set_next_id(std::int64_t id) { next_id_ = id; }

  // Stable compaction: survivors keep their relative order and their ids.
  void erase_dead() {
    std::size_t first_dead = 0;
    while (first_dead < size() && alive_[first_dead]) ++first_dead;
    if (first_dead == size()) return;
    // alive_ is compacted last (see for_each_array), so it is still the
    // original mask while the other arrays are compacted.
    for_each_array([this, first_dead](auto& a) {
      std::size_t kept = first_dead;
      for (std::size_t i = first_dead; i < a.size(); ++i)
        if (alive_[i]) a[kept++] = std::move(a[i]);
      a.resize(kept);
    });
  }

  // new[k] = old[order[k]] for every array; order must be a permutation of 0..size()-1.
  void permute(const std::vector<std::size_t>& order) {
    if (order.size() != size())
      throw std::invalid_argument("partc: ParticleSet::permute: order has the wrong size");
    // In parallel: after a rebuild the order is scattered (md's particles
    // cross several cells a step), and the gathers wait on memory.
    for_each_array([&order](auto& a) {
      std::remove_reference_t<decltype(a)> sorted(order.size());
      parallel_for(order.size(), LoopWork::light, [&](std::size_t k) {
        assert(order[k] < a.size());
        sorted[k] = a[order[k]];
      });
      a.swap(sorted);
    });
  }

  // f(const char* name, const std::vector<S>& values): "p" first, then each Var in order.
  template <class F>
  void for_each_variable(F&& f) const {
    f("p", positions_);
    (f(Vars::name, get<Vars>()), ...);
  }
  template <class F>
  void for_each_variable(F&& f) {
    f("p", positions_);
    (f(Vars::name, get<Vars>()), ...);
  }

 private:
  template <class Var>
  static constexpr std::size_t index_of() {
    static_assert((0 + ... + int{std::is_same_v<Var, Vars>}) == 1,
                  "Var must be listed exactly once in this ParticleSet's variables");
    constexpr bool matches[] = {std::is_same_v<Var, Vars>..., false};
    std::size_t i = 0;
    while (!matches[i]) ++i;
    return i;
  }

  std::size_t append(const Position& position, std::int64_t id) {
    positions_.push_back(position);
    ids_.push_back(id);
    std::apply([](auto&... v) { (v.emplace_back(), ...); }, vars_);  // value-initialised: 0
    alive_.push_back(1);
    return positions_.size() - 1;
  }

  // Applies fn to every array; alive_ comes last because erase_dead reads it as the mask.
  template <class Fn>
  void for_each_array(Fn&& fn) {
    fn(positions_);
    fn(ids_);
    std::apply([&fn](auto&... v) { (fn(v), ...); }, vars_);
    fn(alive_);
  }

  std::vector<Position> positions_;
  std::vector<std::int64_t> ids_;
  std::vector<std::uint8_t> alive_;
  std::tuple<std::vector<storage_t<typename Vars::type>>...> vars_;
  std::int64_t next_id_ = 0;
};

template <int D, class... Vars>
using ParticleSet = BasicParticleSet<Vec<D>, Vars...>;

}  // namespace partc
