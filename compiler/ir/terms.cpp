#include "ir/terms.hpp"

#include <algorithm>
#include <cstddef>
#include <memory>

#include "ir/visitor.hpp"

namespace partc::ir {

std::vector<Term> split_terms(const Expr& value, std::size_t n) {
  std::vector<Term> terms;
  Expr rest = value;
  for (; n > 1; --n) {
    auto b = as<Binary>(rest);
    terms.insert(terms.begin(), {b->rhs, b->op == BinaryOp::Sub});
    rest = b->lhs;
  }
  if (rest->kind == ExprKind::Unary && as<Unary>(rest)->op == UnaryOp::Neg && !terms.empty())
    terms.insert(terms.begin(), {as<Unary>(rest)->operand, true});
  else
    terms.insert(terms.begin(), {rest, false});
  return terms;
}

Expr join_terms(const std::vector<Term>& terms, Location loc) {
  Expr out = terms.front().minus
                 ? std::make_shared<Unary>(terms.front().value->type, UnaryOp::Neg,
                                           terms.front().value, loc)
                 : terms.front().value;
  for (std::size_t k = 1; k < terms.size(); ++k)
    out = std::make_shared<Binary>(out->type, terms[k].minus ? BinaryOp::Sub : BinaryOp::Add, out,
                                   terms[k].value, loc);
  return out;
}

Expr zero_of(Type type, int dim, Location loc) {
  if (type != Type::Vec) return std::make_shared<Literal>(type, 0, loc);
  return std::make_shared<MakeVec>(
      std::vector<Expr>(dim, std::make_shared<Literal>(Type::Real, 0, loc)), loc);
}

std::vector<Statement::Without> parts_without(const Statement& st) {
  if (!st.without.empty()) return st.without;
  std::vector<Statement::Without> out;
  if (!st.terms_by_origin || st.origins.size() < 2) return out;
  const std::vector<Term> terms = split_terms(st.value, st.origins.size());
  for (std::size_t o = 0; o < terms.size(); ++o) {
    std::vector<Term> rest = terms;
    rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(o));
    out.push_back({{o}, join_terms(rest, st.value->loc)});
  }
  return out;
}

static bool holds_sum(const Expr& value, int sum) {
  const std::vector<const Accumulate*> sums = accumulations_in(value);
  return std::any_of(sums.begin(), sums.end(), [&](const Accumulate* acc) { return acc->id == sum; });
}

std::vector<std::size_t> origins_of_sum(const Statement& st, int sum) {
  const std::vector<Statement::Without> parts = parts_without(st);
  std::vector<std::size_t> out, rest;
  for (const Statement::Without& part : parts)
    if (!holds_sum(part.value, sum)) out.insert(out.end(), part.origins.begin(), part.origins.end());
  for (std::size_t o = 0; o < st.origins.size(); ++o)
    if (std::none_of(parts.begin(), parts.end(), [&](const Statement::Without& part) {
          return std::find(part.origins.begin(), part.origins.end(), o) != part.origins.end();
        }))
      rest.push_back(o);
  if (out.empty()) out = rest;
  if (out.empty())
    for (std::size_t o = 0; o < st.origins.size(); ++o) out.push_back(o);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace partc::ir
