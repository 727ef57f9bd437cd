// The terms of a statement that channel merging joined, one per effect
// instance (Statement::terms_by_origin): fold_zero_terms removes the terms a
// constant 0 cancels, and --profile times the statement without each one
// (and fusion keeps those parts for the statement it makes).
#pragma once

#include <cstddef>
#include <vector>

#include "ir/ir.hpp"

namespace partc::ir {

// One term of a contribution: its value and whether it is subtracted.
struct Term {
  Expr value;
  bool minus;
};

// The n terms instantiation joined, t1 + t2 - t3 ... (left to right, the
// first perhaps negated); one term when n is 1, whatever its shape.
std::vector<Term> split_terms(const Expr& value, std::size_t n);

// The terms joined again, as instantiation joins them.
Expr join_terms(const std::vector<Term>& terms, Location loc);

// 0 of a type: 0, or a vec of dim zeros (what is left of all-zero terms).
Expr zero_of(Type type, int dim, Location loc);

// The statement's value without some of its origins, for --profile: the
// parts fusion recorded (Statement::without), else one per merged term;
// none for a statement of one effect or of unsplit terms.
std::vector<Statement::Without> parts_without(const Statement& st);

// The origins (indices) whose terms hold the accumulation `sum` of st: those
// of the parts without it (parts_without), else the origins no part leaves
// out (a fused pass's reader), else all of them (a statement of one effect,
// or of unsplit terms). For --profile: which effects a search serves, and
// which sums a statement keeps without an effect.
std::vector<std::size_t> origins_of_sum(const Statement& st, int sum);

}  // namespace partc::ir
