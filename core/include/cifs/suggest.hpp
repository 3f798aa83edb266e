// SPDX-License-Identifier: MIT
// cifs — "did you mean …?": the one edit-distance helper behind the suggestions for mistyped names
// (command-line options and commands, scheme names, format names).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cifs {

/// Edits between two words: insertions, deletions, substitutions and swaps of neighbouring letters
/// (optimal string alignment), case ignored and '_' the same as '-'.
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate nearest to `word` when it is near enough to be a typo of it (at most a third of the
/// longer word's letters edited, at least one; ties go to the first candidate); none otherwise or
/// when `word` is one of them.
std::optional<std::string> nearest(std::string_view word, const std::vector<std::string>& candidates);

/// "; did you mean catmull-clark?" after an "unknown …" message, or "" when nothing is near.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace cifs
