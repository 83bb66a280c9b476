#include <gtest/gtest.h>

#include "mesohex/core/vec.h"

using mesohex::Vec3;

TEST(Vec3, CrossOfAxesIsRightHanded) {
    EXPECT_EQ(mesohex::cross(Vec3{1, 0, 0}, Vec3{0, 1, 0}), (Vec3{0, 0, 1}));
    EXPECT_DOUBLE_EQ(mesohex::det3(Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}), 1.0);
}

TEST(Vec3, NormalizedZeroStaysZero) {
    EXPECT_EQ(mesohex::normalized(Vec3{}), (Vec3{}));
    EXPECT_DOUBLE_EQ(mesohex::norm(mesohex::normalized(Vec3{3, 4, 0})), 1.0);
}
