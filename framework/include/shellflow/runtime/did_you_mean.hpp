#pragma once
// "Did you mean" suggestions for misspelt keys, plugin names and choices.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace shellflow::runtime {

/// Edit distance (optimal string alignment: a swap of neighbours costs 1), case-sensitive.
int edit_distance(std::string_view a, std::string_view b);

/// The candidate closest to `word` if it is close enough to be a likely typo
/// (distance at most a third of the word's length, at least 1; case differences are free).
std::optional<std::string> closest_match(std::string_view word,
                                         const std::vector<std::string>& candidates);

/// " (did you mean 'x'?)" or "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace shellflow::runtime
