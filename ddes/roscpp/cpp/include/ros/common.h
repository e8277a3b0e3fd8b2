// ddes roscpp: roscpp's version macros and ROSCPP_DECL.
#ifndef ROSCPP_COMMON_H
#define ROSCPP_COMMON_H

#include <assert.h>
#include <stddef.h>
#include <stdint.h>
#include <string>

#include <boost/shared_array.hpp>

#include <ros/assert.h>
#include <ros/forwards.h>
#include <ros/macros.h>
#include <ros/serialized_message.h>

// The roscpp release ddes's roscpp follows (ROS 1 Noetic).
#define ROS_VERSION_MAJOR 1
#define ROS_VERSION_MINOR 15
#define ROS_VERSION_PATCH 15
#define ROS_VERSION_COMBINED(major, minor, patch) (((major) << 20) | ((minor) << 10) | (patch))
#define ROS_VERSION ROS_VERSION_COMBINED(ROS_VERSION_MAJOR, ROS_VERSION_MINOR, ROS_VERSION_PATCH)

#define ROS_VERSION_GE(major1, minor1, patch1, major2, minor2, patch2) \
  (ROS_VERSION_COMBINED(major1, minor1, patch1) >= ROS_VERSION_COMBINED(major2, minor2, patch2))
#define ROS_VERSION_MINIMUM(major, minor, patch) \
  ROS_VERSION_GE(ROS_VERSION_MAJOR, ROS_VERSION_MINOR, ROS_VERSION_PATCH, major, minor, patch)

/// ddes's roscpp is a static library: nothing to import or export.
#define ROSCPP_DECL

namespace ros
{

/// roscpp blocks signals in its own threads; ddes's roscpp starts none, so this does nothing.
void disableAllSignalsInThisThread();

}  // namespace ros

#endif  // ROSCPP_COMMON_H
