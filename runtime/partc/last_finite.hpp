// partc/last_finite.hpp: a copy of the last model state found finite, kept
// so that a numerical blow-up loses no work. The driver writes it as CSV,
// which --input reads back: resume with a smaller time step, or look at the
// particles just before the blow-up.
//
//   LastFinite kept(model);            // holds nothing until the first take
//   kept.take(model, step);            // after each check that passed
//   kept.write([](set) { return path; })  // on a blow-up
//
// Surprises:
// - A copy costs one pass over the state, as the check before it does; the
//   copy reuses its storage, so taking it allocates only when a set grows.
//   Copies are taken only when a check passes, so --check-every M thins both.
// - The copy holds the particles (ids, positions, variables, the next id), not
//   observables or the model's time: a resumed run starts its clock at 0.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "partc/csv.hpp"

namespace partc {

class LastFinite {
 public:
  template <class Model>
  explicit LastFinite(const Model& model) {
    model.for_each_set([&](const char* name, const auto& set) {
      sets_.push_back(std::make_unique<Copy<std::decay_t<decltype(set)>>>(name));
    });
  }

  // The sets come in for_each_set's order, so the k-th copy has the k-th type.
  template <class Model>
  void take(const Model& model, std::int64_t step) {
    std::size_t k = 0;
    model.for_each_set([&](const char*, const auto& set) {
      static_cast<Copy<std::decay_t<decltype(set)>>&>(*sets_[k++]).set = set;
    });
    step_ = step;
  }

  bool empty() const { return step_ < 0; }
  std::int64_t step() const { return step_; }

  // Writes each set to path_of(set name); returns the paths written.
  std::vector<std::string> write(
      const std::function<std::string(const std::string&)>& path_of) const {
    std::vector<std::string> paths;
    for (const auto& copy : sets_) {
      paths.push_back(path_of(copy->name));
      copy->write(paths.back());
    }
    return paths;
  }

 private:
  struct Kept {
    explicit Kept(std::string set_name) : name(std::move(set_name)) {}
    virtual ~Kept() = default;
    virtual void write(const std::string& path) const = 0;
    std::string name;
  };
  template <class Set>
  struct Copy final : Kept {
    explicit Copy(const char* set_name) : Kept(set_name) {}  // empty until the first take
    void write(const std::string& path) const override { write_csv(path, set); }
    Set set;
  };

  std::vector<std::unique_ptr<Kept>> sets_;
  std::int64_t step_ = -1;
};

}  // namespace partc
