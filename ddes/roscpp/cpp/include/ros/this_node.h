// ddes roscpp: ros::this_node, the node's name and namespace as the world resolved them.
#ifndef ROSCPP_THIS_NODE_H
#define ROSCPP_THIS_NODE_H

#include <string>

#include <ros/common.h>
#include <ros/forwards.h>

namespace ros
{
namespace this_node
{

/// The node's fully resolved name ("/talker", "/ns/listener_1234...").
const std::string& getName();
/// The node's namespace ("/" by default).
const std::string& getNamespace();
/// The resolved topics this process advertises.
void getAdvertisedTopics(V_string& topics);
/// The resolved topics this process subscribes to.
void getSubscribedTopics(V_string& topics);

}  // namespace this_node
}  // namespace ros

#endif  // ROSCPP_THIS_NODE_H
