// partc/io/set_view.hpp: SetView, a particle set seen as named columns of
// numbers, whatever its variables' types, so that what reads a whole set
// (the CSV and VTK writers, the driver's summary, the last finite state) is
// compiled once in the runtime library rather than for every model's set type.
//
//   const SetView view = view_of("P", set);  // pointers into the set's arrays
//   write_csv(path, view);                   // csv.hpp
//   visit_column(view.columns[c], [&](const auto* values) { ... });
//
// A column is one variable of for_each_variable ("p" first): its values are
// size * components numbers of one element type, a particle's components
// consecutive (a Vec<D, T> array is D T's per particle, without padding).
// visit_column gives the typed pointer back: const Vec<D, T>* for a vec (D =
// 1 .. 4), const T* for a scalar, so that library code computes on a column
// exactly as a model's own template would (norm in float for a float vec).
//
// Surprises: a view points into the set; it is stale once the set grows,
// shrinks or is reordered. bool variables are their stored std::uint8_t.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "partc/finite.hpp"  // StorageTraits
#include "partc/vec.hpp"

namespace partc {

// How a column's numbers are stored.
enum class Element { f64, f32, i64, u8 };

template <class T>
constexpr Element element_of() {
  if constexpr (std::is_same_v<T, double>)
    return Element::f64;
  else if constexpr (std::is_same_v<T, float>)
    return Element::f32;
  else if constexpr (std::is_same_v<T, std::int64_t>)
    return Element::i64;
  else {
    static_assert(std::is_same_v<T, std::uint8_t>, "a column holds double, float, int64 or uint8");
    return Element::u8;
  }
}

constexpr std::size_t element_size(Element element) {
  switch (element) {
    case Element::f64:
    case Element::i64: return 8;
    case Element::f32: return 4;
    case Element::u8: break;
  }
  return 1;
}

struct ColumnView {
  const char* name;  // the variable's: "p" for the positions
  Element element;
  int components;  // D for a Vec<D, T>, else 1
  bool is_vec;
  const void* data;

  std::size_t bytes(std::size_t size) const {
    return size * static_cast<std::size_t>(components) * element_size(element);
  }
};

struct SetView {
  std::string name;
  int dim = 0;
  std::size_t size = 0;
  std::size_t bytes_per_particle = 0;
  const std::int64_t* ids = nullptr;
  std::vector<ColumnView> columns;  // for_each_variable's order: "p" first
};

// Points `view` at `set`, reusing its storage (no allocation once it has
// held as many columns): the driver refreshes its views after every step.
template <class Set>
void view_into(SetView& view, const char* name, const Set& set) {
  view.name = name;
  view.dim = Set::dim;
  view.size = set.size();
  view.bytes_per_particle = Set::bytes_per_particle;
  view.ids = set.ids().data();
  view.columns.clear();
  set.for_each_variable([&](const char* variable, const auto& values) {
    using S = typename std::decay_t<decltype(values)>::value_type;
    using Traits = StorageTraits<S>;
    static_assert(sizeof(S) == Traits::components * sizeof(typename Traits::component_type),
                  "a stored value is its components, unpadded");
    view.columns.push_back({variable, element_of<typename Traits::component_type>(),
                            Traits::components, Traits::is_vec, values.data()});
  });
}

template <class Set>
SetView view_of(const char* name, const Set& set) {
  SetView view;
  view_into(view, name, set);
  return view;
}

namespace detail {

template <class T, class F>
void visit_elements(const ColumnView& column, F& f) {
  if constexpr (std::is_floating_point_v<T>) {
    if (column.is_vec) {  // back to the type view_of took the pointer of
      switch (column.components) {
        case 1: return f(static_cast<const Vec<1, T>*>(column.data));
        case 2: return f(static_cast<const Vec<2, T>*>(column.data));
        case 3: return f(static_cast<const Vec<3, T>*>(column.data));
        case 4: return f(static_cast<const Vec<4, T>*>(column.data));
        default: throw std::logic_error("partc: a vec column of more than 4 components");
      }
    }
  }
  f(static_cast<const T*>(column.data));
}

}  // namespace detail

// f(values) with the column's typed pointer (see the top of the file).
template <class F>
void visit_column(const ColumnView& column, F&& f) {
  switch (column.element) {
    case Element::f64: return detail::visit_elements<double>(column, f);
    case Element::f32: return detail::visit_elements<float>(column, f);
    case Element::i64: return detail::visit_elements<std::int64_t>(column, f);
    case Element::u8: return detail::visit_elements<std::uint8_t>(column, f);
  }
}

}  // namespace partc
