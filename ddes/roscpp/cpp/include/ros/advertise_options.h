// ddes roscpp: ros::AdvertiseOptions, everything NodeHandle::advertise needs.
#ifndef ROSCPP_ADVERTISE_OPTIONS_H
#define ROSCPP_ADVERTISE_OPTIONS_H

#include <string>

#include <ros/forwards.h>
#include <ros/message_traits.h>

namespace ros
{

struct AdvertiseOptions
{
  AdvertiseOptions() : queue_size(0), callback_queue(0), latch(false), has_header(false) {}

  AdvertiseOptions(const std::string& _topic, uint32_t _queue_size, const std::string& _md5sum,
                   const std::string& _datatype, const std::string& _message_definition,
                   const SubscriberStatusCallback& _connect_cb = SubscriberStatusCallback(),
                   const SubscriberStatusCallback& _disconnect_cb = SubscriberStatusCallback())
  : topic(_topic), queue_size(_queue_size), md5sum(_md5sum), datatype(_datatype),
    message_definition(_message_definition), connect_cb(_connect_cb), disconnect_cb(_disconnect_cb),
    callback_queue(0), latch(false), has_header(false)
  {}

  template <class M>
  void init(const std::string& _topic, uint32_t _queue_size,
            const SubscriberStatusCallback& _connect_cb = SubscriberStatusCallback(),
            const SubscriberStatusCallback& _disconnect_cb = SubscriberStatusCallback())
  {
    topic = _topic;
    queue_size = _queue_size;
    connect_cb = _connect_cb;
    disconnect_cb = _disconnect_cb;
    md5sum = message_traits::md5sum<M>();
    datatype = message_traits::datatype<M>();
    message_definition = message_traits::definition<M>();
    has_header = message_traits::hasHeader<M>();
  }

  std::string topic;
  uint32_t queue_size;
  std::string md5sum;
  std::string datatype;
  std::string message_definition;
  SubscriberStatusCallback connect_cb;     ///< a subscriber connected
  SubscriberStatusCallback disconnect_cb;  ///< a subscriber went away
  CallbackQueueInterface* callback_queue;  ///< where connect_cb/disconnect_cb run (0: global)
  VoidConstPtr tracked_object;
  bool latch;  ///< the last message goes to every later subscriber
  bool has_header;

  template <class M>
  static AdvertiseOptions create(const std::string& topic, uint32_t queue_size,
                                 const SubscriberStatusCallback& connect_cb,
                                 const SubscriberStatusCallback& disconnect_cb, const VoidConstPtr& tracked_object,
                                 CallbackQueueInterface* queue)
  {
    AdvertiseOptions ops;
    ops.init<M>(topic, queue_size, connect_cb, disconnect_cb);
    ops.tracked_object = tracked_object;
    ops.callback_queue = queue;
    return ops;
  }
};

}  // namespace ros

#endif  // ROSCPP_ADVERTISE_OPTIONS_H
