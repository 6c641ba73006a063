#pragma once
// Numbers as an operator types them and as our files hold them: decimal only. strtod alone
// would also take "0x10" (16), "inf", "nan" and "1e400"; a command bar that flies "takeoff 0x10"
// to 16 m, or a CLI that ignores "--focal nan", does what nobody asked.
#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

namespace CLI {
class App;
}

namespace uav {

// [+-]digits[.digits][e[+-]digits] (or [+-].digits...), the whole text, finite as a double;
// nullopt otherwise (hexadecimal, inf, nan, an overflow, trailing characters, empty).
std::optional<double> ParseDecimal(std::string_view text);
// "a,b,c" with `count` ParseDecimal numbers between `separator`s; nullopt otherwise.
std::optional<std::vector<double>> ParseDecimalList(std::string_view text, std::size_t count, char separator = ',');

// Every number-taking option of `app` and its subcommands (CLI11 type FLOAT, INT, UINT) accepts
// only ParseDecimal's numbers (whole ones for INT/UINT): "--focal nan" or "--frames 0x10" is
// refused naming the option. Call after the options are declared, before parsing.
void RequireDecimalNumbers(CLI::App& app);

}  // namespace uav
