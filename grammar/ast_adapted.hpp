// Boost.Fusion views of the AST structs, so X3 sequences can fill them.
// Single-member structs are filled by semantic actions in rules_def.hpp
// instead (X3 mishandles one-element fusion sequences).
#pragma once

#include <boost/fusion/include/adapt_struct.hpp>

#include "ast/ast.hpp"

BOOST_FUSION_ADAPT_STRUCT(partc::ast::Indexed, var, label)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::Target, var, label)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::BinaryOp, op, rhs)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::Chain, first, rest)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::Unary, op, operand)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::Postfix, base, components)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::LabelBinding, label, sets)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::Call, callee, args)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::Assignment, name, target, op, value)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::SolveStatement, name, unknown, lhs, rhs)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::ScheduleOption, key, value)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::ScheduleSubject, name, member)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::ScheduleItem, subject, options)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::BoundaryClause, kind, axes)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::DomainDecl, lo, hi, boundaries)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::ParamDecl, name, type, value)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::ConstDecl, name, value)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::ObservableDecl, name, type, value)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::OutputDecl, set, names, every)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::VarDecl, mirrored, name, type, value)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::FnParam, name, type)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::FnDecl, name, params, value)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::ParticlesDecl, name, count, vars)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::StageBlock, kind, words, body)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::IterateBlock, until, limit, body)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::EffectParam, is_const, name, type, value)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::OwnsItem, local, mirrored, name, type, value, channel)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::AccessItem, kind, name, type)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::ProvidesItem, name, type)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::SlotsItem, kind, names)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::AtItem, slot, statement)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::EffectDecl, name, params, sets, items)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::UseArgument, is_const, name, value)
BOOST_FUSION_ADAPT_STRUCT(partc::ast::UseDecl, module, args, sets, alias)
