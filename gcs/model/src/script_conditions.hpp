#pragma once
// What the script's parser, runner and condition evaluator share (internal to the model).
#include <string>
#include <vector>

namespace uav::gcs::script_detail {

bool ToNumber(const std::string& s, double* v);
std::string Format(double v);
// Splits a condition into clauses of {lhs, op, rhs[, tol]}; throws on malformed input.
std::vector<std::vector<std::string>> Clauses(const std::vector<std::string>& tokens);

}  // namespace uav::gcs::script_detail
