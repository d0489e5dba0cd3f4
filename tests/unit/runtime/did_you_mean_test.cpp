#include "shellflow/runtime/did_you_mean.hpp"

#include <gtest/gtest.h>

namespace shellflow::runtime {

TEST(DidYouMean, EditDistanceKnownValues) {
  EXPECT_EQ(edit_distance("", ""), 0);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3);  // the textbook example
  EXPECT_EQ(edit_distance("stiffness", "stifness"), 1);
  EXPECT_EQ(edit_distance("abc", ""), 3);
  EXPECT_EQ(edit_distance("widht", "width"), 1);  // a swap of neighbours is one edit
}

TEST(DidYouMean, SuggestsOnlyCloseCandidates) {
  const std::vector<std::string> keys{"stiffness", "damping", "surface_density"};
  EXPECT_EQ(closest_match("stifness", keys), "stiffness");
  EXPECT_EQ(closest_match("Damping", keys), "damping");  // case is free
  EXPECT_FALSE(closest_match("gravity", keys).has_value());
  EXPECT_EQ(did_you_mean("xyz", keys), "");
}

}  // namespace shellflow::runtime
