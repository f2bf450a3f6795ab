#pragma once
/// Small parsing helpers shared by the subcommands.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace mg::cli {

/// Parses the whole of `text` (an optional leading '+') as a finite double; throws `InputError`
/// naming `what` ("expected a number" / "expected a finite number").
double parse_number(const std::string& what, const std::string& text);

/// Parses the whole of `text` as a non-negative integer; throws `InputError` naming `what`.
std::uint64_t parse_unsigned(const std::string& what, const std::string& text);

/// Parses "a,b" (or "a,b,c" with N = 3) into finite doubles; throws `InputError` naming `what`.
template <std::size_t N>
std::array<double, N> parse_vector(const std::string& what, const std::string& text);

/// Parses "a,b,c" into names (no empty entries); throws `InputError` naming `what`.
std::vector<std::string> parse_names(const std::string& what, const std::string& text);

}  // namespace mg::cli
