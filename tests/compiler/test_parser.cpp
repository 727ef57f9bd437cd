// The front end: what the grammar builds, where it says nodes are, and the
// types sema gives expressions.
#include <catch2/catch.hpp>

#include "ast/printer.hpp"
#include "driver/pipeline.hpp"
#include "grammar/parser.hpp"
#include "ir/printer.hpp"
#include "support/diagnostics.hpp"

namespace {

const char* const kHeader =
    "model m\n"
    "dim 2\n"
    "domain lo=(0, 0) hi=(1, 1) periodic=(x)\n"
    "param N: int = 10\n"
    "particles P(N) {\n"
    "  v: vec = 0\n"
    "  m: real = 1\n"
    "}\n";

std::string ast_of(const std::string& text) {
  partc::SourceFile file("t.part", text);
  return partc::ast::to_string(partc::parse_program(file), file);
}

std::string ir_statement(const std::string& statement) {
  partc::SourceFile file("t.part", std::string(kHeader) + "step {\n  " + statement + "\n}\n");
  const partc::Compilation c = partc::analyse(file);
  const partc::ir::Statement& st = c.model.stages.at(0).statements.at(0);
  return partc::ir::to_string(st.value, c.model, st.labels) + " : " +
         partc::ir::type_name(st.value->type);
}

// The first diagnostic for a whole file.
partc::Diagnostic first_error(const std::string& text) {
  partc::SourceFile file("t.part", text);
  try {
    partc::analyse(file);
  } catch (const partc::CompileError& e) {
    return e.diagnostics().front();
  }
  FAIL("no error for:\n" << text);
  return {};
}

}  // namespace

TEST_CASE("operator precedence and associativity", "[parser]") {
  CHECK(ast_of("const a = 1 + 2 * 3 - 4\n") == "(const a (- (+ 1 (* 2 3)) 4)) @1:1\n");
  CHECK(ast_of("const a = not x < 1 and y or z\n") ==
        "(const a (or (and (not (< x 1)) y) z)) @1:1\n");
  CHECK(ast_of("const a = -|v| / 2.5e-3\n") == "(const a (/ (- (norm v)) 0.0025)) @1:1\n");
}

TEST_CASE("accumulations, label bindings, components and comments", "[parser]") {
  CHECK(ast_of("step { v[i] += sum(j in Q, |dx| < r, dx) # force\n}\n") ==
        "(step) @1:1\n  (+= v[i] (call sum (in j Q) (< (norm dx) r) dx)) @1:8\n");
  CHECK(ast_of("init P {\n  m[i] = v[i].y; m[i] *= 2\n}\n") ==
        "(init P) @1:1\n  (= m[i] (.y v[i])) @2:3\n  (*= m[i] 2) @2:18\n");
}

TEST_CASE("locations span exactly the node's text", "[parser]") {
  // The error for the statement points at `q`, and the caret width is q's.
  const partc::Diagnostic d = first_error(std::string(kHeader) + "step {\n  m[i] = 2 * q   # c\n}\n");
  CHECK(d.message == "unknown name 'q'");
  partc::SourceFile file("t.part", std::string(kHeader) + "step {\n  m[i] = 2 * q   # c\n}\n");
  CHECK(file.slice(d.loc) == "q");
  CHECK(file.line_column(d.loc.begin).line == 10);
  CHECK(file.line_column(d.loc.begin).column == 14);
}

TEST_CASE("types: ints, reals, vecs and their promotions", "[sema]") {
  CHECK(ir_statement("m[i] = N / 4") == "(N / 4) : real");  // int / int is real division
  CHECK(ir_statement("m[i] = |v[i]| + N") == "(norm(v[i]) + N) : real");
  CHECK(ir_statement("v[i] = 2 * v[i] / m[i]") == "((2 * v[i]) / m[i]) : vec");
  CHECK(ir_statement("m[i] = count(j, |dx| < 0.1)") ==
        "count#0(j in P, (norm(dx(i->j)) < 0.1), 1):int : int");
  CHECK(ir_statement("m[i] = max(j, true, m[j]) - min(m[i], 2)") ==
        "(max#0(j in P, true, m[j]):real - min(m[i], 2)) : real");
  CHECK(ir_statement("v[i] = 0") == "vec(0, 0) : vec");  // constants broadcast
}

TEST_CASE("diagnostics name the problem and its place", "[sema]") {
  const std::string h = kHeader;
  CHECK(first_error(h + "step {\n  m[i] = v[i]\n}\n").message ==
        "cannot store a vec in variable m, which is a real");
  CHECK(first_error(h + "step {\n  v[i] += dot(v[i], 1)\n}\n").message ==
        "dot() needs vecs, not an int");
  CHECK(first_error(h + "init {\n  m[i] = sum(j, |dx| < 1, uniform())\n}\n").message ==
        "random numbers inside an accumulation are not supported");
  CHECK(first_error("model m\ndim 5\n").message == "missing 'domain lo=(...) hi=(...)' declaration");
  CHECK(first_error("model m\ndim 5\ndomain lo=(0) hi=(1)\n").message ==
        "dim must be 1, 2, 3 or 4");
}
