// ddes roscpp: ROS_STATIC_ASSERT (C++11 static_assert).
#ifndef ROSCPP_STATIC_ASSERT_H
#define ROSCPP_STATIC_ASSERT_H

#ifndef ROS_STATIC_ASSERT
#define ROS_STATIC_ASSERT(cond) static_assert(cond, #cond)
#endif

#endif  // ROSCPP_STATIC_ASSERT_H
