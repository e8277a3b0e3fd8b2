// Counts std_msgs/String messages on chatter (benchmarks/bench_roscpp.py).
#include "ros/ros.h"
#include "std_msgs/String.h"

static long heard = 0;

void callback(const std_msgs::String::ConstPtr& msg) {
  heard += static_cast<long>(msg->data.size() > 0);
}

int main(int argc, char** argv) {
  ros::init(argc, argv, "bench_listener");
  ros::NodeHandle n;
  ros::Subscriber sub = n.subscribe("chatter", 1000, callback);
  ros::spin();
  return 0;
}
