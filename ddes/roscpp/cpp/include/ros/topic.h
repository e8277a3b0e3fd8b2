// ddes roscpp: ros::topic::waitForMessage, the next message on a topic (WAIT_FOR_MESSAGE: the
// world subscribes, waits and answers; no callback of the node runs meanwhile, as roscpp
// waits on a queue of its own).  Null on timeout or shutdown; a zero timeout waits forever.
#ifndef ROSCPP_TOPIC_H
#define ROSCPP_TOPIC_H

#include <string>
#include <vector>

#include <boost/make_shared.hpp>
#include <boost/shared_ptr.hpp>

#include <ros/message_traits.h>
#include <ros/node_handle.h>
#include <ros/serialization.h>

namespace ros
{
namespace topic
{

namespace ddes_detail
{
/// The message's bytes, or false (timeout, shutdown).
bool waitForMessageBytes(const std::string& topic, NodeHandle& nh, ros::Duration timeout, const char* datatype,
                         const char* md5sum, std::vector<uint8_t>& bytes);
}  // namespace ddes_detail

template <class M>
boost::shared_ptr<M const> waitForMessage(const std::string& topic, NodeHandle& nh, ros::Duration timeout)
{
  std::vector<uint8_t> bytes;
  if (!ddes_detail::waitForMessageBytes(topic, nh, timeout, message_traits::datatype<M>(),
                                        message_traits::md5sum<M>(), bytes))
    return boost::shared_ptr<M const>();
  boost::shared_ptr<M> msg = boost::make_shared<M>();
  serialization::IStream stream(bytes.data(), static_cast<uint32_t>(bytes.size()));
  serialization::deserialize(stream, *msg);
  return msg;
}

template <class M>
boost::shared_ptr<M const> waitForMessage(const std::string& topic)
{
  ros::NodeHandle nh;
  return waitForMessage<M>(topic, nh, ros::Duration());
}

template <class M>
boost::shared_ptr<M const> waitForMessage(const std::string& topic, ros::Duration timeout)
{
  ros::NodeHandle nh;
  return waitForMessage<M>(topic, nh, timeout);
}

template <class M>
boost::shared_ptr<M const> waitForMessage(const std::string& topic, ros::NodeHandle& nh)
{
  return waitForMessage<M>(topic, nh, ros::Duration());
}

}  // namespace topic
}  // namespace ros

#endif  // ROSCPP_TOPIC_H
