// ddes roscpp: ros::TransportHints.  Accepted and kept, as roscpp's API has them; ddes's world
// delivers every message itself (there are no TCP or UDP links), so they change nothing.
#ifndef ROSCPP_TRANSPORT_HINTS_H
#define ROSCPP_TRANSPORT_HINTS_H

#include <cstdlib>
#include <string>
#include <vector>

#include <ros/datatypes.h>

namespace ros
{

class TransportHints
{
public:
  /// Prefer a reliable transport (TCP).
  TransportHints& reliable() { tcp(); return *this; }
  TransportHints& tcp() { transports_.push_back("TCP"); return *this; }
  TransportHints& tcpNoDelay(bool nodelay = true)
  {
    options_["tcp_nodelay"] = nodelay ? "true" : "false";
    return *this;
  }
  bool getTCPNoDelay() { return options_["tcp_nodelay"] == "true"; }
  TransportHints& maxDatagramSize(int size)
  {
    options_["max_datagram_size"] = std::to_string(size);
    return *this;
  }
  int getMaxDatagramSize()
  {
    M_string::iterator it = options_.find("max_datagram_size");
    return it == options_.end() ? 0 : std::atoi(it->second.c_str());
  }
  /// Prefer an unreliable transport (UDP).
  TransportHints& unreliable() { udp(); return *this; }
  TransportHints& udp() { transports_.push_back("UDP"); return *this; }
  const V_string& getTransports() { return transports_; }
  const M_string& getOptions() { return options_; }

private:
  V_string transports_;
  M_string options_;
};

}  // namespace ros

#endif  // ROSCPP_TRANSPORT_HINTS_H
