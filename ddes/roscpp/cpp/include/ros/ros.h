// ddes roscpp: everything a roscpp node includes with <ros/ros.h>.
#ifndef ROSCPP_ROS_H
#define ROSCPP_ROS_H

#include <ros/assert.h>
#include <ros/common.h>
#include <ros/console.h>
#include <ros/init.h>
#include <ros/master.h>
#include <ros/names.h>
#include <ros/node_handle.h>
#include <ros/param.h>
#include <ros/publisher.h>
#include <ros/rate.h>
#include <ros/service.h>
#include <ros/service_server.h>
#include <ros/single_subscriber_publisher.h>
#include <ros/subscriber.h>
#include <ros/this_node.h>
#include <ros/time.h>
#include <ros/topic.h>
#include <ros/types.h>

#endif  // ROSCPP_ROS_H
