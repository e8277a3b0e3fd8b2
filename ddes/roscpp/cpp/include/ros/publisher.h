// ddes roscpp: ros::Publisher, a handle on an advertised topic.
//
// Copies share one advertisement; it is withdrawn (UNADVERTISE) when shutdown() is called or
// the last copy is destroyed, as in roscpp.  publish() serializes the message and hands its
// bytes to the world (PUBLISH), which delivers them to the topic's subscribers.
#ifndef ROSCPP_PUBLISHER_HANDLE_H
#define ROSCPP_PUBLISHER_HANDLE_H

#include <string>
#include <vector>

#include <boost/shared_ptr.hpp>

#include <ros/assert.h>
#include <ros/common.h>
#include <ros/forwards.h>
#include <ros/message_traits.h>
#include <ros/serialization.h>

namespace ros
{

namespace ddes
{
class PublisherImpl;
/// A buffer of at least `size` bytes for serializing one outgoing message (per thread).
uint8_t* scratchBuffer(uint32_t size);
}  // namespace ddes

class Publisher
{
public:
  Publisher() {}
  Publisher(const Publisher& rhs);
  ~Publisher();
  Publisher& operator=(const Publisher& other) = default;

  template <typename M>
  void publish(const boost::shared_ptr<M>& message) const
  {
    publish(*message);
  }

  template <typename M>
  void publish(const M& message) const
  {
    namespace ser = serialization;
    if (!impl_)
    {
      ROS_ASSERT_MSG(false, "Call to publish() on an invalid Publisher");
      return;
    }
    if (!isValidImpl())
    {
      ROS_ASSERT_MSG(false, "Call to publish() on an invalid Publisher (topic [%s])", getTopic().c_str());
      return;
    }
    const uint32_t len = ser::serializationLength(message);
    uint8_t* buf = ddes::scratchBuffer(len);
    ser::OStream stream(buf, len);
    ser::serialize(stream, message);
    publishSerialized(buf, len);
  }

  /// Withdraws the advertisement (every copy becomes invalid).
  void shutdown();
  /// The resolved topic.
  std::string getTopic() const;
  /// How many subscribers the topic has in the world now.
  uint32_t getNumSubscribers() const;
  bool isLatched() const;

  operator void*() const { return (impl_ && isValidImpl()) ? reinterpret_cast<void*>(1) : static_cast<void*>(0); }

  bool operator<(const Publisher& rhs) const { return impl_ < rhs.impl_; }
  bool operator==(const Publisher& rhs) const { return impl_ == rhs.impl_; }
  bool operator!=(const Publisher& rhs) const { return impl_ != rhs.impl_; }

private:
  explicit Publisher(const boost::shared_ptr<ddes::PublisherImpl>& impl);
  bool isValidImpl() const;
  void publishSerialized(const uint8_t* data, uint32_t len) const;

  boost::shared_ptr<ddes::PublisherImpl> impl_;

  friend class NodeHandle;
  friend class SingleSubscriberPublisher;
};
typedef std::vector<Publisher> V_Publisher;

}  // namespace ros

#endif  // ROSCPP_PUBLISHER_HANDLE_H
