// ddes roscpp: ros::master.  The master is the world's; ddes's protocol does not list topics
// or nodes to a node, so getTopics and getNodes return false.
#ifndef ROSCPP_MASTER_H
#define ROSCPP_MASTER_H

#include <string>
#include <vector>

#include <ros/forwards.h>
#include <xmlrpcpp/XmlRpcValue.h>

namespace ros
{
namespace master
{

struct TopicInfo
{
  TopicInfo() {}
  TopicInfo(const std::string& _name, const std::string& _datatype) : name(_name), datatype(_datatype) {}
  std::string name;
  std::string datatype;
};
typedef std::vector<TopicInfo> V_TopicInfo;

const std::string& getHost();
uint32_t getPort();
/// ROS_MASTER_URI (roscpp's default when unset).
const std::string& getURI();
/// Whether the master (the world) is reachable: the node is connected and not shut down.
bool check();
bool getTopics(V_TopicInfo& topics);
bool getNodes(V_string& nodes);
void setRetryTimeout(ros::WallDuration timeout);

}  // namespace master
}  // namespace ros

#endif  // ROSCPP_MASTER_H
