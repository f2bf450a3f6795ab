#pragma once
/// Small parsing helpers shared by the subcommands.
#include <array>
#include <string>
#include <vector>

namespace mg::cli {

/// Parses "a,b" (or "a,b,c" with N = 3) into finite doubles; throws `InputError` naming `what`.
template <std::size_t N>
std::array<double, N> parse_vector(const std::string& what, const std::string& text);

/// Parses "a,b,c" into names (no empty entries); throws `InputError` naming `what`.
std::vector<std::string> parse_names(const std::string& what, const std::string& text);

}  // namespace mg::cli
