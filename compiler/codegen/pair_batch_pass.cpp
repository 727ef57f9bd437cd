// Emits the batch kernel of sums over neighbours whose terms have a vector
// form (analysis/vector_terms.cpp), a lambda the walks that pack pairs into
// batches call: a search's or half Verlet lists' pair walk
// (for_each_pair_batch, each pair once) and a search's packed per-particle
// queries (for_each_near_batch, each particle's neighbours). A vector loop
// computes each sum's term for a vector of pairs at a time
// (codegen/simd_term.cpp) into columns, and a scalar loop then gives each
// pair's term to i, and +-term to j when the batch holds each pair once,
// into the same per-particle member vectors the scalar walk (pair_pass)
// fills. One kernel serves both walks, so it is compiled once. From the pair
// walk, i's terms arrive one by one rather than summed first, so the totals
// differ from the scalar walk's by roundings, not by thread count. With float
// arithmetic (the members share it: statement fusion sees to that) the vector
// loop runs on float lanes, twice the pairs a step, into float columns, and
// the scatter adds each float term into the double sums.
#include <fmt/format.h>

#include <algorithm>

#include "codegen/model_emitter.hpp"
#include "codegen/simd_term.hpp"

namespace partc::codegen {

bool ModelEmitter::vector_terms(const Loop& l) const {
  for (const Accumulate* acc : l.members) {
    const auto fact = facts_.vector_terms.find(acc->id);
    if (fact == facts_.vector_terms.end() || !fact->second.vector) return false;
  }
  return true;
}

std::string ModelEmitter::batch_kernel(const Loop& l, const ExpressionNames& names,
                                       const std::string& count, NameTable& locals,
                                       const std::string& kernel, BatchWalks walks) {
  const std::string i = names.labels[0];
  const std::string j = names.labels[l.members.front()->label];
  const std::string name = locals.fresh("batch_terms"), batch = locals.fresh("pairs");
  const std::string tag = locals.fresh("d"), k = locals.fresh("k");
  for (const Accumulate* acc : l.members)
    linef("{}.assign({}, {});", pair_sums_member(*acc, kernel), count, identity(*acc));
  const Precision arithmetic = facts_.vector_terms.at(l.members.front()->id).arithmetic;
  const bool floats = arithmetic == Precision::Float;
  switch (walks) {
    case BatchWalks::pairs:
      line("// Each pair once (Newton's third law), on vectors of pairs: a batch's terms computed");
      line("// together (partc/simd), then given to i and j.");
      break;
    case BatchWalks::pairs_or_queries:
      line("// Each pair once (Newton's third law), or each particle's neighbours, on vectors of");
      line("// pairs: a batch's terms computed together (partc/simd), then given to i, and to j");
      line("// when the batch holds each pair once.");
      break;
    case BatchWalks::queries:
      line("// Each particle's neighbours, on vectors of pairs: a batch's terms computed together");
      line("// (partc/simd), then summed into i in its query's order.");
      break;
  }
  if (floats) {
    line("// The terms on float lanes, twice the pairs a vector (schedule: arithmetic = float),");
    line("// each added into the double sums.");
  } else {
    line("// The terms on double lanes (schedule: arithmetic = double).");
  }
  linef("const auto {} = [&](partc::simd::PairBatch<{}>& {}) {{", name, m_.dim, batch);
  line("namespace hn = partc::simd::hn;");
  linef("const partc::simd::{} {};", floats ? "Float" : "Real", tag);
  const SimdTermCode code =
      emit_simd_terms(l.members, m_, names, locals, batch, k, tag, arithmetic);
  // One column per component of each term, kept for the scatter.
  std::vector<std::vector<std::string>> columns;
  std::size_t column_count = 0;
  for (const auto& term : code.terms) column_count += term.size();
  const char* column_type = floats ? "float" : "double";
  const std::string of_type = floats ? "<float>" : "";
  linef("{}.columns{}({});", batch, of_type, column_count);
  std::size_t next = 0;
  for (std::size_t a = 0; a < l.members.size(); ++a) {
    columns.emplace_back();
    for (std::size_t c = 0; c < code.terms[a].size(); ++c) {
      columns.back().push_back(locals.fresh("term_" + std::to_string(next)));
      linef("{}* const {} = {}.column{}({});", column_type, columns.back().back(), batch, of_type,
            next++);
    }
  }
  for (const std::string& text : code.setup) line(text);
  // The padding's terms are computed too (from harmless entries) and never read.
  linef("for (std::size_t {0} = 0; {0} < {1}.padded({3}); {0} += hn::Lanes({2})) {{", k, batch, tag,
        floats ? fmt::format("hn::Lanes({})", tag) : "");
  for (const std::string& text : code.lines) line(text);
  for (std::size_t a = 0; a < l.members.size(); ++a)
    for (std::size_t c = 0; c < columns[a].size(); ++c)
      linef("hn::StoreU({}, {}, {} + {});", code.terms[a][c], tag, columns[a][c], k);
  line("}");
  linef("for (std::size_t {0} = 0; {0} < {1}.count(); ++{0}) {{", k, batch);
  if (walks == BatchWalks::queries)
    linef("const std::size_t {} = {}.i()[{}];", i, batch, k);
  else
    linef("const std::size_t {} = {}.i()[{}], {} = {}.j()[{}];", i, batch, k, j, batch, k);
  for (std::size_t a = 0; a < l.members.size(); ++a) {
    const Accumulate& acc = *l.members[a];
    std::vector<std::string> parts;
    for (const std::string& column : columns[a]) parts.push_back(column + "[" + k + "]");
    const std::string term = acc.type == Type::Vec
                                 ? fmt::format("Vec{{{{{}}}}}", fmt::join(parts, ", "))
                                 : parts.front();
    const std::string& sums = pair_sums_.at(acc.id).first;
    linef("{}[{}] += {};", sums, i, term);
    if (walks == BatchWalks::queries) continue;
    linef("if ({}{} != {}) {}[{}] {}= {};",
          walks == BatchWalks::pairs_or_queries ? batch + ".each_pair_once() && " : "", j, i, sums,
          j, facts_.symmetry.at(acc.id).sign > 0 ? "+" : "-", term);
  }
  line("}");
  line("};");
  return name;
}

bool ModelEmitter::packed_queries(const Loop& l) const {
  return std::all_of(l.members.begin(), l.members.end(), [&](const Accumulate* acc) {
    return facts_.vector_terms.at(acc->id).packed_queries;
  });
}

bool ModelEmitter::batch_self_pair(const Loop& l) const {
  return std::any_of(l.members.begin(), l.members.end(), [&](const Accumulate* acc) {
    return facts_.vector_terms.at(acc->id).self_pair;
  });
}

}  // namespace partc::codegen
