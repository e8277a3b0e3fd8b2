// ddes roscpp: ros::SingleSubscriberPublisher, what a publisher's connect/disconnect callback
// receives: the subscriber's name, the topic, and publish() to that one subscriber (the
// PUBLISH_ONE frame of docs/external-nodes.md).
#ifndef ROSCPP_SINGLE_SUBSCRIBER_PUBLISHER_H
#define ROSCPP_SINGLE_SUBSCRIBER_PUBLISHER_H

#include <string>

#include <boost/noncopyable.hpp>
#include <boost/shared_ptr.hpp>

#include <ros/forwards.h>
#include <ros/publisher.h>
#include <ros/serialization.h>

namespace ros
{

class SingleSubscriberPublisher : public boost::noncopyable
{
public:
  SingleSubscriberPublisher(const boost::shared_ptr<ddes::PublisherImpl>& publisher,
                            const std::string& subscriber);
  ~SingleSubscriberPublisher();

  template <class M>
  void publish(const boost::shared_ptr<M const>& message) const
  {
    publish(*message);
  }

  template <class M>
  void publish(const boost::shared_ptr<M>& message) const
  {
    publish(*message);
  }

  template <class M>
  void publish(const M& message) const
  {
    namespace ser = serialization;
    const uint32_t len = ser::serializationLength(message);
    uint8_t* buf = ddes::scratchBuffer(len);
    ser::OStream stream(buf, len);
    ser::serialize(stream, message);
    publishSerialized(buf, len);
  }

  std::string getTopic() const;
  std::string getSubscriberName() const;

private:
  void publishSerialized(const uint8_t* data, uint32_t len) const;

  boost::shared_ptr<ddes::PublisherImpl> publisher_;
  std::string subscriber_;
};

}  // namespace ros

#endif  // ROSCPP_SINGLE_SUBSCRIBER_PUBLISHER_H
