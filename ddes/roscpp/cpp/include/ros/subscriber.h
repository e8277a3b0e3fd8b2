// ddes roscpp: ros::Subscriber, a handle on a subscription.  Copies share it; it ends
// (UNSUBSCRIBE) when shutdown() is called or the last copy is destroyed, as in roscpp.
#ifndef ROSCPP_SUBSCRIBER_HANDLE_H
#define ROSCPP_SUBSCRIBER_HANDLE_H

#include <string>
#include <vector>

#include <boost/shared_ptr.hpp>

#include <ros/common.h>
#include <ros/forwards.h>

namespace ros
{

namespace ddes
{
class SubscriberImpl;
}

class Subscriber
{
public:
  Subscriber() {}
  Subscriber(const Subscriber& rhs);
  ~Subscriber();
  Subscriber& operator=(const Subscriber& other) = default;

  /// Ends the subscription (every copy becomes invalid).
  void shutdown();
  /// The resolved topic.
  std::string getTopic() const;
  /// How many publishers the topic has in the world now.
  uint32_t getNumPublishers() const;

  operator void*() const { return (impl_ && isValidImpl()) ? reinterpret_cast<void*>(1) : static_cast<void*>(0); }

  bool operator<(const Subscriber& rhs) const { return impl_ < rhs.impl_; }
  bool operator==(const Subscriber& rhs) const { return impl_ == rhs.impl_; }
  bool operator!=(const Subscriber& rhs) const { return impl_ != rhs.impl_; }

private:
  explicit Subscriber(const boost::shared_ptr<ddes::SubscriberImpl>& impl);
  bool isValidImpl() const;

  boost::shared_ptr<ddes::SubscriberImpl> impl_;

  friend class NodeHandle;
};
typedef std::vector<Subscriber> V_Subscriber;

}  // namespace ros

#endif  // ROSCPP_SUBSCRIBER_HANDLE_H
