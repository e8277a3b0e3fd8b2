// Publishes argv[1] std_msgs/String messages at argv[2] Hz, then exits (benchmarks/bench_roscpp.py).
#include <cstdlib>
#include <string>

#include "ros/ros.h"
#include "std_msgs/String.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "bench_talker");
  ros::NodeHandle n;
  const long count = argc > 1 ? std::atol(argv[1]) : 1000;
  const double hz = argc > 2 ? std::atof(argv[2]) : 1000.0;
  ros::Publisher pub = n.advertise<std_msgs::String>("chatter", 1000);
  ros::Rate rate(hz);
  rate.sleep();  // the first connection is made meanwhile, as a real talker's
  std_msgs::String msg;
  for (long i = 0; i < count && ros::ok(); ++i) {
    msg.data = "hello world " + std::to_string(i);
    pub.publish(msg);
    rate.sleep();
  }
  return 0;
}
