// What the robot is sent for (nav/target.h): a mapped object's class and measured size against
// the told ones, dimensions only bounded from below, and what rules an object out for the search.
#include <gtest/gtest.h>

#include "planemap/nav/target.h"

namespace planemap::nav {
namespace {

// A mapped object of `label` measured at `dimensions` [m] (x, y horizontal, z the height),
// each whole or only bounded from below.
MapObject Mapped(const std::string& label, const Eigen::Vector3d& dimensions, std::array<bool, 3> whole = {true, true, true}) {
  MapObject o;
  o.label = label;
  o.dimensions = dimensions;
  o.dimension_complete = whole;
  return o;
}

// The gallery's task (configs/scenes/gallery.yaml): a 24 x 21 x 33 cm box, within 5 cm.
TargetDescription GalleryBox() { return {"box", Eigen::Vector3d(0.24, 0.21, 0.33), 0.05}; }

// Of the target's class and size, as `planemap approach` takes a target.
bool Fits(const MapObject& o, const TargetDescription& target) {
  return o.label == target.label && SizeConflict(o, target).empty();
}

TEST(Target, TheBoxMeasuredWithinTheToleranceMatchesInEitherHorizontalOrder) {
  EXPECT_TRUE(Fits(Mapped("box", {0.245, 0.205, 0.34}), GalleryBox()));
  EXPECT_TRUE(Fits(Mapped("box", {0.21, 0.24, 0.33}), GalleryBox())) << "x and y swapped";
  EXPECT_TRUE(Fits(Mapped("box", {0.285, 0.21, 0.33}), GalleryBox())) << "4.5 cm long";
  EXPECT_EQ(SizeConflict(Mapped("box", {0.24, 0.21, 0.33}), GalleryBox()), "");
}

TEST(Target, TheCrateBeforeTheBoxIsAnotherObject) {
  // The gallery's crate: 32 x 28 x 40 cm, a graspable "box" to the frontend.
  const MapObject crate = Mapped("box", {0.32, 0.28, 0.40});
  EXPECT_FALSE(Fits(crate, GalleryBox()));
  EXPECT_TRUE(RuledOut(crate, GalleryBox()));
  const std::string why = SizeConflict(crate, GalleryBox());
  EXPECT_NE(why.find("32 x 28 x 40 cm"), std::string::npos) << why;
  EXPECT_NE(why.find("24 x 21 x 33 cm"), std::string::npos) << why;
  // One dimension 6 cm off is enough.
  EXPECT_FALSE(Fits(Mapped("box", {0.24, 0.21, 0.39}), GalleryBox()));
  EXPECT_FALSE(Fits(Mapped("box", {0.24, 0.15, 0.33}), GalleryBox()));
}

TEST(Target, ADimensionOnlyBoundedFromBelowRulesOutOnlyWhenPastTheSize) {
  // The top unseen: the height is at least 20 cm, which the 33 cm box can be.
  EXPECT_TRUE(Fits(Mapped("box", {0.24, 0.21, 0.20}, {true, true, false}), GalleryBox()));
  // A face cut by the image at 45 cm already: longer than the box can be.
  const MapObject long_face = Mapped("box", {0.45, 0.21, 0.33}, {false, true, true});
  EXPECT_FALSE(Fits(long_face, GalleryBox()));
  EXPECT_TRUE(RuledOut(long_face, GalleryBox()));
  EXPECT_NE(SizeConflict(long_face, GalleryBox()).find("only bounded"), std::string::npos);
}

TEST(Target, WithoutASizeTheClassDecidesAndUnknownsStayCandidates) {
  const TargetDescription any{"box", std::nullopt, 0.05};
  EXPECT_TRUE(Fits(Mapped("box", {0.32, 0.28, 0.40}), any));
  EXPECT_FALSE(Fits(Mapped("locker", {0.5, 0.8, 1.8}), any));
  // A locker with its height measured is ruled out; with the top unseen it may still be a box.
  EXPECT_TRUE(RuledOut(Mapped("locker", {0.5, 0.8, 1.8}), any));
  EXPECT_FALSE(RuledOut(Mapped("locker", {0.5, 0.8, 0.3}, {true, true, false}), any));
  EXPECT_FALSE(RuledOut(Mapped("unknown", {0.3, 0.3, 0.3}), any));
  // An unknown object measured at another size is ruled out once a size is told.
  EXPECT_TRUE(RuledOut(Mapped("unknown", {0.6, 0.3, 0.3}), GalleryBox()));
}

}  // namespace
}  // namespace planemap::nav
