// The Spirit X3 rules of the .part grammar.
//
// Each rule sits under the EBNF production (partc.ebnf) it implements. Its
// name is what the user reads in "expected ..." messages, so names are
// phrases, not identifiers. Expectation points (>) mark where a construct is
// committed: after `param`, a missing ':' is an error, not a backtrack.
// Every rule whose attribute is an AST node records the node's source range
// (see `locate`).
#pragma once

#include <boost/spirit/home/x3.hpp>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <string>
#include <type_traits>

#include "ast/ast.hpp"
#include "grammar/ast_adapted.hpp"

namespace partc::grammar {

namespace x3 = boost::spirit::x3;
using x3::alnum;
using x3::alpha;
using x3::char_;
using x3::digit;
using x3::lexeme;
using x3::lit;
using x3::raw;

using Iterator = std::string::const_iterator;

// Context tag holding the iterator at the start of the file, so node
// locations can be stored as byte offsets.
struct source_begin_tag;

// Where the text of a match ends. Failed attempts to continue a match (an
// optional ';', another '+ term') skip blanks and comments before failing,
// so `last` can lie past them; '#' appears in no token, so stepping back
// over blanks and cutting at a line's first '#' finds the real end.
template <typename It>
It end_of_text(It first, It last) {
  for (;;) {
    while (last != first && std::isspace(static_cast<unsigned char>(*(last - 1)))) --last;
    It line = last;
    while (line != first && *(line - 1) != '\n') --line;
    It hash = std::find(line, last, '#');
    if (hash == last) return last;
    last = hash;
  }
}

// Base of every rule ID: fills in ast::Located::loc on success.
struct locate {
  template <typename It, typename Attribute, typename Context>
  void on_success(It first, It const& last, Attribute& node, Context const& context) {
    if constexpr (std::is_base_of_v<ast::Located, Attribute>) {
      x3::skip_over(first, last, context);  // a rule starts after leading blanks
      const It& begin = x3::get<source_begin_tag>(context);
      node.loc.begin = static_cast<std::uint32_t>(first - begin);
      node.loc.end = static_cast<std::uint32_t>(end_of_text(first, last) - begin);
    }
  }
};

// A reserved word: matches `word` only when no identifier character follows,
// and reads as 'word' in "expected ..." messages.
struct keyword : x3::parser<keyword> {
  using attribute_type = x3::unused_type;
  static bool const has_attribute = false;
  const char* word;
  explicit constexpr keyword(const char* w) : word(w) {}

  template <typename It, typename Context, typename RContext, typename Attribute>
  bool parse(It& first, It const& last, Context const& context, RContext&, Attribute&) const {
    x3::skip_over(first, last, context);
    It it = first;
    for (const char* c = word; *c; ++c, ++it)
      if (it == last || *it != *c) return false;
    if (it != last && (std::isalnum(static_cast<unsigned char>(*it)) || *it == '_')) return false;
    first = it;
    return true;
  }
};

// The same, with the word as the attribute (for operators spelled as words).
struct keyword_string : x3::parser<keyword_string> {
  using attribute_type = std::string;
  const char* word;
  explicit constexpr keyword_string(const char* w) : word(w) {}

  template <typename It, typename Context, typename RContext, typename Attribute>
  bool parse(It& first, It const& last, Context const& context, RContext& rcontext,
             Attribute& attr) const {
    x3::unused_type unused;
    if (!keyword(word).parse(first, last, context, rcontext, unused)) return false;
    x3::traits::move_to(std::string(word), attr);
    return true;
  }
};

}  // namespace partc::grammar

namespace boost::spirit::x3 {
template <>
struct get_info<partc::grammar::keyword> {
  using result_type = std::string;
  std::string operator()(const partc::grammar::keyword& k) const {
    return std::string("'") + k.word + "'";
  }
};
template <>
struct get_info<partc::grammar::keyword_string> {
  using result_type = std::string;
  std::string operator()(const partc::grammar::keyword_string& k) const {
    return std::string("'") + k.word + "'";
  }
};
}  // namespace boost::spirit::x3

namespace partc::grammar {

// Rule IDs. Deriving from `locate` makes a rule record source ranges.
struct identifier_id : locate {};
struct int_literal_id : locate {};
struct real_literal_id : locate {};
struct bool_literal_id : locate {};
struct indexed_id : locate {};
struct expression_id : locate {};
struct and_expr_id : locate {};
struct not_expr_id : locate {};
struct not_op_id : locate {};
struct comparison_id : locate {};
struct additive_id : locate {};
struct multiplicative_id : locate {};
struct unary_id : locate {};
struct negation_id : locate {};
struct postfix_id : locate {};
struct primary_id : locate {};
struct norm_id : locate {};
struct call_id : locate {};
struct argument_id : locate {};
struct label_binding_id : locate {};
struct boundary_clause_id : locate {};
struct or_tail_id : locate {};
struct and_tail_id : locate {};
struct compare_tail_id : locate {};
struct additive_tail_id : locate {};
struct multiplicative_tail_id : locate {};
struct assignment_id : locate {};
struct model_decl_id : locate {};
struct dim_decl_id : locate {};
struct domain_decl_id : locate {};
struct tuple_id : locate {};
struct param_decl_id : locate {};
struct const_decl_id : locate {};
struct observable_decl_id : locate {};
struct timestep_decl_id : locate {};
struct output_decl_id : locate {};
struct target_id : locate {};
struct solve_statement_id : locate {};
struct iterate_block_id : locate {};
struct block_statement_id : locate {};
struct step_number_id : locate {};
struct dim_number_id : locate {};
struct var_decl_id : locate {};
struct fn_decl_id : locate {};
struct schedule_block_id : locate {};
struct schedule_item_id : locate {};
struct schedule_subject_id : locate {};
struct schedule_option_id : locate {};
struct fn_param_id : locate {};
struct particles_decl_id : locate {};
struct stage_block_id : locate {};
struct declaration_id : locate {};
struct module_decl_id : locate {};
struct effect_decl_id : locate {};
struct effect_param_id : locate {};
struct effect_item_id : locate {};
struct owns_item_id : locate {};
struct access_item_id : locate {};
struct provides_item_id : locate {};
struct requires_item_id : locate {};
struct slots_item_id : locate {};
struct at_item_id : locate {};
struct use_decl_id : locate {};
struct use_argument_id : locate {};
struct order_decl_id : locate {};
struct import_decl_id : locate {};
struct end_of_effect_id : locate {};
struct program_id : locate {};
struct end_of_block_id : locate {};
struct end_of_vars_id : locate {};
struct end_of_input_id : locate {};

x3::rule<identifier_id, ast::Identifier> const identifier = "a name";
x3::rule<class identifier_text_id, ast::Identifier> const identifier_text = "a name";
x3::rule<int_literal_id, ast::IntLiteral> const int_literal = "an integer";
x3::rule<class int_literal_text_id, ast::IntLiteral> const int_literal_text = "an integer";
x3::rule<real_literal_id, ast::RealLiteral> const real_literal = "a number";
x3::rule<class real_literal_text_id, ast::RealLiteral> const real_literal_text = "a number";
x3::rule<bool_literal_id, ast::BoolLiteral> const bool_literal = "true or false";
x3::rule<class bool_literal_text_id, ast::BoolLiteral> const bool_literal_text = "true or false";
x3::rule<indexed_id, ast::Indexed> const indexed = "an indexed variable like v[i]";
x3::rule<expression_id, ast::Chain> const expression = "an expression";
x3::rule<and_expr_id, ast::Chain> const and_expr = "an expression";
x3::rule<not_expr_id, ast::Operand> const not_expr = "an expression";
x3::rule<not_op_id, ast::Unary> const not_op = "an expression";
x3::rule<comparison_id, ast::Chain> const comparison = "an expression";
x3::rule<additive_id, ast::Chain> const additive = "an expression";
x3::rule<multiplicative_id, ast::Chain> const multiplicative = "an expression";
x3::rule<unary_id, ast::Operand> const unary = "an expression";
x3::rule<negation_id, ast::Unary> const negation = "an expression";
x3::rule<postfix_id, ast::Postfix> const postfix = "an expression";
x3::rule<primary_id, ast::Operand> const primary = "an expression";
x3::rule<norm_id, ast::Norm> const norm = "a norm |...|";
x3::rule<class norm_text_id, ast::Norm> const norm_text = "a norm |...|";
x3::rule<call_id, ast::Call> const call = "a call";
x3::rule<argument_id, ast::Argument> const argument = "an argument";
x3::rule<label_binding_id, ast::LabelBinding> const label_binding = "a label binding like 'j in Q'";
x3::rule<or_tail_id, ast::BinaryOp> const or_tail = "an expression";
x3::rule<and_tail_id, ast::BinaryOp> const and_tail = "an expression";
x3::rule<compare_tail_id, ast::BinaryOp> const compare_tail = "an expression";
x3::rule<additive_tail_id, ast::BinaryOp> const additive_tail = "an expression";
x3::rule<multiplicative_tail_id, ast::BinaryOp> const multiplicative_tail = "an expression";
x3::rule<assignment_id, ast::Assignment> const assignment = "an assignment";
x3::rule<model_decl_id, ast::ModelDecl> const model_decl = "a model declaration";
x3::rule<class model_decl_text_id, ast::ModelDecl> const model_decl_text = "a model declaration";
x3::rule<dim_decl_id, ast::DimDecl> const dim_decl = "a dim declaration";
x3::rule<class dim_decl_text_id, ast::DimDecl> const dim_decl_text = "a dim declaration";
x3::rule<domain_decl_id, ast::DomainDecl> const domain_decl = "a domain declaration";
x3::rule<boundary_clause_id, ast::BoundaryClause> const boundary_clause =
    "a boundary like 'periodic=(x, y)'";
x3::rule<tuple_id, std::vector<ast::Chain>> const tuple = "a tuple like (0, 0)";
x3::rule<param_decl_id, ast::ParamDecl> const param_decl = "a param declaration";
x3::rule<const_decl_id, ast::ConstDecl> const const_decl = "a const declaration";
x3::rule<observable_decl_id, ast::ObservableDecl> const observable_decl =
    "an observable declaration";
x3::rule<timestep_decl_id, ast::TimestepDecl> const timestep_decl = "a timestep declaration";
x3::rule<class timestep_decl_text_id, ast::TimestepDecl> const timestep_decl_text =
    "a timestep declaration";
x3::rule<output_decl_id, ast::OutputDecl> const output_decl = "an output declaration";
x3::rule<target_id, ast::Target> const target = "a variable like v[i], or an observable";
x3::rule<solve_statement_id, ast::SolveStatement> const solve_statement = "a solve statement";
x3::rule<block_statement_id, ast::BlockStatement> const block_statement = "a statement";
x3::rule<iterate_block_id, ast::IterateBlock> const iterate_block = "an iterate block";
x3::rule<step_number_id, ast::Identifier> const step_number = "step";
x3::rule<class step_number_text_id, ast::Identifier> const step_number_text = "step";
x3::rule<dim_number_id, ast::Identifier> const dim_number = "dim";
x3::rule<class dim_number_text_id, ast::Identifier> const dim_number_text = "dim";
x3::rule<var_decl_id, ast::VarDecl> const var_decl = "a variable declaration";
x3::rule<fn_decl_id, ast::FnDecl> const fn_decl = "a function declaration";
x3::rule<schedule_block_id, ast::ScheduleBlock> const schedule_block = "a schedule block";
x3::rule<class schedule_block_text_id, ast::ScheduleBlock> const schedule_block_text =
    "a schedule block";
x3::rule<schedule_item_id, ast::ScheduleItem> const schedule_item = "a schedule entry";
x3::rule<schedule_subject_id, ast::ScheduleSubject> const schedule_subject =
    "a statement name or SET.variable";
x3::rule<class end_of_schedule_id> const end_of_schedule =
    "a schedule entry like force: search = cell_list or P.v: precision = float, or '}'";
x3::rule<schedule_option_id, ast::ScheduleOption> const schedule_option =
    "an option like search = kd_tree or skin = 0.3";
x3::rule<fn_param_id, ast::FnParam> const fn_param = "a parameter like r: real";
x3::rule<particles_decl_id, ast::ParticlesDecl> const particles_decl = "a particles declaration";
x3::rule<stage_block_id, ast::StageBlock> const stage_block = "an init, step or stage block";
x3::rule<declaration_id, ast::Declaration> const declaration = "a declaration";
x3::rule<module_decl_id, ast::ModuleDecl> const module_decl = "a module declaration";
x3::rule<class module_decl_text_id, ast::ModuleDecl> const module_decl_text =
    "a module declaration";
x3::rule<class dotted_name_id, std::vector<ast::Identifier>> const dotted_name =
    "a module name like pair.lj";
x3::rule<effect_decl_id, ast::EffectDecl> const effect_decl = "an effect declaration";
x3::rule<effect_param_id, ast::EffectParam> const effect_param =
    "a parameter like eps: real = 1";
x3::rule<effect_item_id, ast::EffectItem> const effect_item = "an effect item";
x3::rule<owns_item_id, ast::OwnsItem> const owns_item = "an owns declaration";
x3::rule<access_item_id, ast::AccessItem> const access_item =
    "a reads, sets or contributes declaration";
x3::rule<provides_item_id, ast::ProvidesItem> const provides_item = "a provides declaration";
x3::rule<requires_item_id, ast::RequiresItem> const requires_item =
    "a requirement, like requires kernel == 0 or kernel == 1";
x3::rule<class requires_item_text_id, ast::RequiresItem> const requires_item_text =
    "a requirement, like requires kernel == 0 or kernel == 1";
x3::rule<slots_item_id, ast::SlotsItem> const slots_item = "a slots or prime declaration";
x3::rule<at_item_id, ast::AtItem> const at_item = "a statement at a slot, like at force: f[i] += ...";
x3::rule<end_of_effect_id> const end_of_effect =
    "an effect item (owns, reads, sets, contributes, provides, slots, prime, at, const, "
    "timestep) or '}'";
x3::rule<use_decl_id, ast::UseDecl> const use_decl = "a use declaration";
x3::rule<use_argument_id, ast::UseArgument> const use_argument = "an argument like eps = 1.2";
x3::rule<order_decl_id, ast::OrderDecl> const order_decl = "an order declaration";
x3::rule<class order_decl_text_id, ast::OrderDecl> const order_decl_text = "an order declaration";
x3::rule<import_decl_id, ast::ImportDecl> const import_decl = "an import declaration";
x3::rule<class import_decl_text_id, ast::ImportDecl> const import_decl_text =
    "an import declaration";
x3::rule<program_id, std::vector<ast::Declaration>> const program = "a program";
x3::rule<end_of_block_id> const end_of_block = "an assignment like x[i] = ... or '}'";
x3::rule<end_of_vars_id> const end_of_vars = "a variable declaration like v: vec = 0, or '}'";
x3::rule<end_of_input_id> const end_of_input =
    "a declaration (model, dim, domain, param, const, observable, timestep, output, fn, "
    "particles, init, step, stage, schedule, use, order, import, module or effect)";

// Semantic actions fill single-member nodes. X3 calls no on_success for a
// rule whose definition holds an action, so each such rule (`*_text`) is
// wrapped in a plain rule of the same attribute that records the range.
auto const set_name = [](auto& ctx) {
  _val(ctx).name.assign(_attr(ctx).begin(), _attr(ctx).end());
};
auto const set_int = [](auto& ctx) {
  const auto& text = _attr(ctx);
  std::int64_t value = 0;
  const char* b = &*text.begin();
  const char* e = b + (text.end() - text.begin());
  if (std::from_chars(b, e, value).ec != std::errc())
    throw x3::expectation_failure<Iterator>(text.begin(), "an integer that fits in 64 bits");
  _val(ctx).value = value;
};
auto const set_real = [](auto& ctx) {
  const std::string text(_attr(ctx).begin(), _attr(ctx).end());
  _val(ctx).value = std::strtod(text.c_str(), nullptr);
};
auto const set_true = [](auto& ctx) {
  _val(ctx).value = true;
};
auto const set_false = [](auto& ctx) {
  _val(ctx).value = false;
};
auto const set_inner = [](auto& ctx) {
  _val(ctx).inner = std::move(_attr(ctx));
};
auto const set_model_name = [](auto& ctx) {
  _val(ctx).name = std::move(_attr(ctx));
};
auto const set_dim_value = [](auto& ctx) {
  _val(ctx).value = std::move(_attr(ctx));
};
auto const set_step_name = [](auto& ctx) { _val(ctx).name = "step"; };

x3::symbols<> const reserved_words = [] {
  x3::symbols<> s;
  s.add("model")("dim")("domain")("param")("const")("observable")("timestep")("output")("every")(
      "fn")("particles")("schedule")("init")("step")("stage")("solve")("iterate")("until")(
      "limit")("mirrored")("and")("or")("not")("true")("false")("in");
  return s;
}();
auto const word_char = alnum | char_('_');

// identifier = ( letter | "_" ) , { letter | digit | "_" } - keyword ;
auto const identifier_def = identifier_text;
auto const identifier_text_def =
    raw[lexeme[!(reserved_words >> !word_char) >> (alpha | char_('_')) >> *word_char]][set_name];

// int_literal = digit , { digit } ;
auto const int_literal_def = int_literal_text;
auto const int_literal_text_def = raw[lexeme[+digit >> !(word_char | '.')]][set_int];

// real_literal = digit , { digit } , ( "." , { digit } , [ exponent ] | exponent )
//              | "." , digit , { digit } , [ exponent ] ;
auto const exponent = (lit('e') | 'E') >> -(lit('+') | '-') >> +digit;
auto const real_literal_def = real_literal_text;
auto const real_literal_text_def =
    raw[lexeme[(+digit >> (('.' >> *digit >> -exponent) | exponent)) |
               ('.' >> +digit >> -exponent)]][set_real];

// bool_literal = "true" | "false" ;
auto const bool_literal_def = bool_literal_text;
auto const bool_literal_text_def = keyword("true")[set_true] | keyword("false")[set_false];

// indexed = identifier , "[" , identifier , "]" ;
auto const indexed_def = identifier >> '[' > identifier > ']';

// expression = and_expr , { "or" , and_expr } ;
auto const expression_def = and_expr >> *or_tail;
auto const or_tail_def = keyword_string("or") > and_expr;

// and_expr = not_expr , { "and" , not_expr } ;
auto const and_expr_def = not_expr >> *and_tail;
auto const and_tail_def = keyword_string("and") > not_expr;

// not_expr = "not" , not_expr | comparison ;
auto const not_expr_def = not_op | comparison;
auto const not_op_def = keyword_string("not") > not_expr;

// comparison = additive , { compare_op , additive } ;
auto const compare_op = x3::string("<=") | x3::string(">=") | x3::string("==") |
                        x3::string("!=") | x3::string("<") | x3::string(">");
auto const comparison_def = additive >> *compare_tail;
auto const compare_tail_def = compare_op > additive;

// additive = multiplicative , { ( "+" | "-" ) , multiplicative } ;
auto const additive_def = multiplicative >> *additive_tail;
auto const additive_tail_def = (x3::string("+") | x3::string("-")) >> !lit('=') > multiplicative;

// multiplicative = unary , { ( "*" | "//" | "/" ) , unary } ;
auto const multiplicative_def = unary >> *multiplicative_tail;
auto const multiplicative_tail_def =
    (x3::string("*") | x3::string("//") | x3::string("/")) >> !lit('=') > unary;

// unary = ( "-" | "+" ) , unary | postfix ;
auto const unary_def = negation | postfix;
auto const negation_def = (x3::string("-") | x3::string("+")) > unary;

// postfix = primary , { "." , identifier } ;
auto const postfix_def = primary >> *('.' > identifier);

// primary = real_literal | int_literal | bool_literal | norm | call
//         | indexed | identifier | step_number | dim_number | "(" , expression , ")" ;
auto const primary_def = real_literal | int_literal | bool_literal | norm | call | indexed |
                         identifier | step_number | dim_number | ('(' > expression > ')');

// step_number = "step" ;  (the keyword, read as the number of steps taken)
auto const step_number_def = step_number_text;
auto const step_number_text_def = keyword("step")[set_step_name];

// dim_number = "dim" ;  (the keyword, read as the model's dimension: for
// modules written for any dimension, as a kernel's normalisation)
auto const set_dim_name = [](auto& ctx) { _val(ctx).name = "dim"; };
auto const dim_number_def = dim_number_text;
auto const dim_number_text_def = keyword("dim")[set_dim_name];

// norm = "|" , expression , "|" ;
auto const norm_def = norm_text;
auto const norm_text_def = ('|' > expression > '|')[set_inner];

// call = identifier , "(" , [ argument , { "," , argument } ] , ")" ;
auto const call_def = identifier >> '(' > -(argument % ',') > ')';

// argument = label_binding | expression ;
auto const argument_def = label_binding | expression;

// label_binding = identifier , "in" , ( identifier | "(" , identifier , { "," , identifier } , ")" ) ;
auto const label_binding_def =
    identifier >> keyword("in") > (('(' > (identifier % ',') > ')') | x3::repeat(1)[identifier]);

// assignment = [ identifier , ":" ] , target , assign_op , expression , [ ";" ] ;
// target     = identifier , [ "[" , identifier , "]" ] ;
// assign_op  = "=" | "+=" | "-=" | "*=" | "/=" ;
auto const assign_op = x3::rule<class assign_op_id, std::string>{"'=', '+=', '-=', '*=' or '/='"} =
    x3::string("+=") | x3::string("-=") | x3::string("*=") | x3::string("/=") |
    (x3::string("=") >> !lit('='));
// The lookahead (&) commits to a name only when a ':' follows: X3 would
// otherwise keep the half-parsed name of `v[i]` in the optional.
auto const statement_name = &(identifier >> ':') >> identifier >> ':';
auto const assignment_def = -statement_name >> target > assign_op > expression > -lit(';');
auto const target_def = identifier >> -('[' > identifier > ']');

// block_statement = iterate_block | solve_statement | assignment ;
// iterate_block   = "iterate" , "until" , expression , "limit" , expression ,
//                   "{" , { block_statement } , "}" ;
// solve_statement = [ identifier , ":" ] , "solve" , target , ":" , expression , "=" ,
//                   expression , [ ";" ] ;
auto const block_statement_def = iterate_block | solve_statement | assignment;
auto const iterate_block_def = keyword("iterate") > keyword("until") > expression >
                               keyword("limit") > expression > '{' > *block_statement >
                               end_of_block;
auto const solve_statement_def = -statement_name >> keyword("solve") > target > ':' > expression >
                                 '=' > expression > -lit(';');

// model_decl = "model" , identifier ;
auto const model_decl_def = model_decl_text;
auto const model_decl_text_def = (keyword("model") > identifier)[set_model_name];

// dim_decl = "dim" , int_literal ;
auto const dim_decl_def = dim_decl_text;
auto const dim_decl_text_def = (keyword("dim") > int_literal)[set_dim_value];

// domain_decl = "domain" , "lo" , "=" , tuple , "hi" , "=" , tuple , { boundary_clause } ;
auto const domain_decl_def = keyword("domain") > keyword("lo") > '=' > tuple > keyword("hi") >
                             '=' > tuple > *(&(identifier >> '=') >> boundary_clause);

// boundary_clause = identifier , "=" , "(" , [ identifier , { "," , identifier } ] , ")" ;
// (a clause is a name and '=': a word without one begins the next
// declaration, as `use` or `import` may)
auto const boundary_clause_def = identifier > '=' > '(' > -(identifier % ',') > ')';

// tuple = "(" , expression , { "," , expression } , ")" ;
auto const tuple_def = '(' > (expression % ',') > ')';

// param_decl = "param" , identifier , ":" , identifier , "=" , expression ;
auto const param_decl_def = keyword("param") > identifier > ':' > identifier > '=' > expression;

// const_decl = "const" , identifier , "=" , expression ;
auto const const_decl_def = keyword("const") > identifier > '=' > expression;

// observable_decl = "observable" , identifier , ":" , identifier , "=" , expression ;
auto const observable_decl_def = keyword("observable") > identifier > ':' > identifier > '=' >
                                 expression;

// timestep_decl = "timestep" , "=" , expression ;
auto const set_timestep = [](auto& ctx) { _val(ctx).value = std::move(_attr(ctx)); };
auto const timestep_decl_def = timestep_decl_text;
auto const timestep_decl_text_def = (keyword("timestep") > '=' > expression)[set_timestep];

// output_decl = "output" , [ identifier , ":" ] , identifier , { "," , identifier } ,
//   [ "every" , expression ] ;
// (The lookahead: a failed optional would still leave its identifier in the attribute.)
auto const output_decl_def = keyword("output") > -(&(identifier >> ':') >> identifier >> ':') >
                             (identifier % ',') > -(keyword("every") > expression);

// fn_decl = "fn" , identifier , "(" , [ fn_param , { "," , fn_param } ] , ")" ,
//           "=" , expression ;
// fn_param = identifier , ":" , identifier ;
auto const fn_decl_def = keyword("fn") > identifier > '(' > -(fn_param % ',') > ')' > '=' >
                         expression;
auto const fn_param_def = identifier > ':' > identifier;

// var_decl = identifier , ":" , identifier , [ "=" , expression ] ;
auto const var_decl_def =
    x3::matches[keyword("mirrored")] >> identifier > ':' > identifier > -('=' > expression);

// particles_decl = "particles" , identifier , "(" , expression , ")" , "{" , { var_decl } , "}" ;
auto const particles_decl_def = keyword("particles") > identifier > '(' > expression > ')' > '{' >
                                *var_decl > end_of_vars;
auto const end_of_vars_def = lit('}');

// stage_block = ( "init" | "step" ) , [ identifier ] , "{" , { block_statement } , "}"
//             | "stage" , identifier , [ identifier ] , "{" , { block_statement } , "}" ;
auto const stage_block_def =
    (keyword_string("init") | keyword_string("step") | keyword_string("stage")) > *identifier >
    '{' > *block_statement > end_of_block;
auto const end_of_block_def = lit('}');

// schedule_block = "schedule" , "{" , { schedule_item } , "}" ;
// schedule_item  = [ schedule_subject , ":" ] , option , { "," , option } ;
// schedule_subject = identifier , [ "." , identifier ] ;
// option         = identifier , "=" , expression ;
auto const set_items = [](auto& ctx) { _val(ctx).items = std::move(_attr(ctx)); };
auto const schedule_block_def = schedule_block_text;
auto const schedule_block_text_def =
    (keyword("schedule") > '{' > *schedule_item > end_of_schedule)[set_items];
auto const end_of_schedule_def = lit('}');
auto const schedule_item_def =
    -(&(schedule_subject >> ':') >> schedule_subject >> ':') >> (schedule_option % ',');
auto const schedule_subject_def = identifier >> -('.' > identifier);
auto const schedule_option_def = identifier > '=' > expression;

// Modules and scenes. Their words (module, effect, use, on, as, owns, ...)
// are not reserved: each can begin only where no name can, so models may
// keep using them as names.
// module_decl = "module" , dotted_name ;
// dotted_name = identifier , { "." , identifier } ;
auto const set_module_name = [](auto& ctx) { _val(ctx).name = std::move(_attr(ctx)); };
auto const module_decl_def = module_decl_text;
auto const module_decl_text_def = (keyword("module") > dotted_name)[set_module_name];
auto const dotted_name_def = identifier % '.';

// effect_decl  = "effect" , identifier , "(" , [ effect_param , { "," , effect_param } ] , ")" ,
//                "on" , identifier , { "," , identifier } , "{" , { effect_item } , "}" ;
// effect_param = [ "const" ] , identifier , ":" , identifier , "=" , expression ;
auto const effect_decl_def = keyword("effect") > identifier > '(' > -(effect_param % ',') > ')' >
                             keyword("on") > (identifier % ',') > '{' > *effect_item >
                             end_of_effect;
auto const end_of_effect_def = lit('}');
auto const effect_param_def =
    x3::matches[keyword("const")] >> identifier > ':' > identifier > '=' > expression;

// effect_item   = owns_item | access_item | provides_item | slots_item | at_item
//               | const_decl | timestep_decl | requires_item ;
// owns_item     = "owns" , [ "local" ] , [ "mirrored" ] , identifier , ":" , identifier ,
//                 [ "=" , expression ] , [ "channel" ] ;
// access_item   = ( "reads" | "sets" | "contributes" ) , identifier , ":" , identifier ;
// provides_item = "provides" , identifier , ":" , identifier ;
// slots_item    = ( "slots" | "prime" ) , identifier , { "," , identifier } ;
// at_item       = "at" , identifier , ":" , assignment ;
auto const effect_item_def = owns_item | access_item | provides_item | slots_item | at_item |
                             const_decl | timestep_decl | requires_item;
auto const owns_item_def = keyword("owns") > x3::matches[keyword("local")] >
                           x3::matches[keyword("mirrored")] > identifier > ':' >
                           identifier > -('=' > expression) > x3::matches[keyword("channel")];
auto const access_item_def =
    (keyword_string("reads") | keyword_string("sets") | keyword_string("contributes")) >
    identifier > ':' > identifier;
auto const provides_item_def = keyword("provides") > identifier > ':' > identifier;
auto const slots_item_def =
    (keyword_string("slots") | keyword_string("prime")) > (identifier % ',');
auto const at_item_def = keyword("at") > identifier > ':' > assignment;
// requires_item = "requires" , expression ;
// (Through a second rule, as timestep_decl: a one-member struct.)
auto const set_condition = [](auto& ctx) { _val(ctx).condition = std::move(_attr(ctx)); };
auto const requires_item_def = requires_item_text;
auto const requires_item_text_def = (keyword("requires") > expression)[set_condition];

// use_decl = "use" , dotted_name , [ "(" , [ use_argument , { "," , use_argument } ] , ")" ] ,
//            "on" , identifier , { "," , identifier } , [ "as" , identifier ] ;
// use_argument = [ "const" ] , identifier , "=" , expression ;
auto const use_decl_def = keyword("use") > dotted_name >
                          -('(' > -(use_argument % ',') > ')') > keyword("on") >
                          (identifier % ',') > -(keyword("as") > identifier);
auto const use_argument_def = x3::matches[keyword("const")] >> identifier > '=' > expression;

// order_decl = "order" , identifier , { "," , identifier } ;
auto const set_instances = [](auto& ctx) { _val(ctx).instances = std::move(_attr(ctx)); };
auto const order_decl_def = order_decl_text;
auto const order_decl_text_def = (keyword("order") > (identifier % ','))[set_instances];

// import_decl = "import" , dotted_name ;
auto const set_import_module = [](auto& ctx) { _val(ctx).module = std::move(_attr(ctx)); };
auto const import_decl_def = import_decl_text;
auto const import_decl_text_def = (keyword("import") > dotted_name)[set_import_module];

// declaration = model_decl | dim_decl | domain_decl | param_decl | const_decl
//             | observable_decl | timestep_decl | output_decl
//             | fn_decl | particles_decl | stage_block | schedule_block
//             | module_decl | effect_decl | use_decl | order_decl | import_decl ;
auto const declaration_def = model_decl | dim_decl | domain_decl | param_decl | const_decl |
                             observable_decl | timestep_decl | output_decl | fn_decl |
                             particles_decl | stage_block | schedule_block | module_decl |
                             effect_decl | use_decl | order_decl | import_decl;

// program = { declaration } ;
auto const program_def = *declaration > end_of_input;
auto const end_of_input_def = x3::eoi;

BOOST_SPIRIT_DEFINE(identifier, identifier_text, int_literal, int_literal_text, real_literal,
                    real_literal_text, bool_literal, bool_literal_text, norm_text, model_decl_text,
                    dim_decl_text, indexed, expression,
                    or_tail, and_expr, and_tail, not_expr, not_op, comparison, compare_tail,
                    additive, additive_tail, multiplicative, multiplicative_tail, unary, negation,
                    postfix, primary, norm, call, argument, label_binding, assignment, model_decl,
                    dim_decl, domain_decl, tuple, param_decl, const_decl, observable_decl,
                    timestep_decl, timestep_decl_text, output_decl, target, solve_statement,
                    iterate_block,
                    block_statement, step_number,
                    step_number_text, fn_decl, fn_param, schedule_block,
                    schedule_block_text, schedule_item, schedule_option, end_of_schedule, var_decl, particles_decl,
                    end_of_vars, stage_block, end_of_block, declaration, program, end_of_input)
// One BOOST_SPIRIT_DEFINE takes a bounded number of rules (Boost.Preprocessor's limit).
BOOST_SPIRIT_DEFINE(boundary_clause, schedule_subject, module_decl, module_decl_text, dotted_name,
                    effect_decl, end_of_effect, effect_param, effect_item, owns_item, access_item,
                    provides_item, slots_item, at_item, use_decl, use_argument, order_decl,
                    order_decl_text, import_decl, import_decl_text, dim_number, dim_number_text)
BOOST_SPIRIT_DEFINE(requires_item, requires_item_text)

// Whitespace and comments from '#' to the end of the line.
auto const skipper = x3::space | lexeme['#' >> *(char_ - x3::eol)];

}  // namespace partc::grammar
