// Spellings of IR operators and functions, as a .part file writes them.
#include "ir/ir.hpp"

namespace partc::ir {

const char* binary_op_spelling(BinaryOp op) {
  switch (op) {
    case BinaryOp::Add: return "+";
    case BinaryOp::Sub: return "-";
    case BinaryOp::Mul: return "*";
    case BinaryOp::Div: return "/";
    case BinaryOp::FloorDiv: return "//";
    case BinaryOp::Lt: return "<";
    case BinaryOp::Le: return "<=";
    case BinaryOp::Gt: return ">";
    case BinaryOp::Ge: return ">=";
    case BinaryOp::Eq: return "==";
    case BinaryOp::Ne: return "!=";
    case BinaryOp::And: return "and";
    case BinaryOp::Or: return "or";
  }
  return "?";
}

const char* function_name(Function f) {
  switch (f) {
    case Function::Exp: return "exp";
    case Function::Log: return "log";
    case Function::Sqrt: return "sqrt";
    case Function::Pow: return "pow";
    case Function::Abs: return "abs";
    case Function::Min: return "min";
    case Function::Max: return "max";
    case Function::Dot: return "dot";
    case Function::Norm: return "norm";
    case Function::Floor: return "floor";
    case Function::Sin: return "sin";
    case Function::Cos: return "cos";
    case Function::Ceil: return "ceil";
    case Function::Round: return "round";
    case Function::Tan: return "tan";
    case Function::Asin: return "asin";
    case Function::Acos: return "acos";
    case Function::Atan: return "atan";
    case Function::Atan2: return "atan2";
    case Function::Tanh: return "tanh";
    case Function::Sign: return "sign";
    case Function::Clamp: return "clamp";
    case Function::Mod: return "mod";
    case Function::Cross: return "cross";
  }
  return "?";
}

const char* reduction_name(Reduction r) {
  switch (r) {
    case Reduction::Sum: return "sum";
    case Reduction::Min: return "min";
    case Reduction::Max: return "max";
    case Reduction::Count: return "count";
  }
  return "?";
}

const char* assign_op_spelling(AssignOp op) {
  switch (op) {
    case AssignOp::Set: return "=";
    case AssignOp::Add: return "+=";
    case AssignOp::Sub: return "-=";
    case AssignOp::Mul: return "*=";
    case AssignOp::Div: return "/=";
  }
  return "?";
}

const char* search_choice_name(SearchChoice c) {
  switch (c) {
    case SearchChoice::Auto: return "auto";
    case SearchChoice::BruteForce: return "brute_force";
    case SearchChoice::CellList: return "cell_list";
    case SearchChoice::KdTree: return "kd_tree";
  }
  return "?";
}

const char* sharing_name(Sharing s) {
  switch (s) {
    case Sharing::Auto: return "auto";
    case Sharing::Shared: return "shared";
    case Sharing::Separate: return "separate";
  }
  return "?";
}

const char* solver_choice_name(SolverChoice c) {
  switch (c) {
    case SolverChoice::Auto: return "auto";
    case SolverChoice::Lu: return "lu";
    case SolverChoice::Cg: return "cg";
    case SolverChoice::Bicgstab: return "bicgstab";
    case SolverChoice::Gmres: return "gmres";
  }
  return "?";
}

const char* dense_method_name(DenseMethod d) {
  switch (d) {
    case DenseMethod::Direct: return "direct";
    case DenseMethod::Fmm: return "fmm";
  }
  return "?";
}

const char* precision_name(Precision p) {
  switch (p) {
    case Precision::Double: return "double";
    case Precision::Float: return "float";
  }
  return "?";
}

int ParticleSet::find_var(const std::string& var_name) const {
  for (std::size_t k = 0; k < vars.size(); ++k)
    if (vars[k].name == var_name) return static_cast<int>(k);
  return -1;
}

std::string accumulation_heading(const Model& m, const Statement& st, const Accumulate& acc) {
  const Label& label = st.labels[acc.label];
  std::string heading = std::string(reduction_name(acc.reduction)) + "(" + label.name;
  if (label.set != st.set) heading += " in " + m.sets[label.set].name;
  return heading + ")";
}

std::string target_name(const Model& m, const Statement& st) {
  if (st.observable >= 0) return m.observables[st.observable].name;
  const ParticleSet& set = m.sets[st.set];
  return (m.sets.size() > 1 ? set.name + "." : "") + set.vars[st.var].name + "[" +
         st.labels[0].name + "]";
}

}  // namespace partc::ir
