// ddes roscpp: ros::SubscribeOptions, everything NodeHandle::subscribe needs.
#ifndef ROSCPP_SUBSCRIBE_OPTIONS_H
#define ROSCPP_SUBSCRIBE_OPTIONS_H

#include <string>

#include <ros/forwards.h>
#include <ros/message_traits.h>
#include <ros/subscription_callback_helper.h>
#include <ros/transport_hints.h>

namespace ros
{

struct SubscribeOptions
{
  SubscribeOptions() : queue_size(1), callback_queue(0), allow_concurrent_callbacks(false) {}

  SubscribeOptions(const std::string& _topic, uint32_t _queue_size, const std::string& _md5sum,
                   const std::string& _datatype)
  : topic(_topic), queue_size(_queue_size), md5sum(_md5sum), datatype(_datatype), callback_queue(0),
    allow_concurrent_callbacks(false)
  {}

  /// For a callback taking P (any ParameterAdapter form).
  template <class P>
  void initByFullCallbackType(const std::string& _topic, uint32_t _queue_size,
                              const boost::function<void(P)>& _callback,
                              const boost::function<boost::shared_ptr<typename ParameterAdapter<P>::Message>(void)>&
                                  factory_fn = DefaultMessageCreator<typename ParameterAdapter<P>::Message>())
  {
    typedef typename ParameterAdapter<P>::Message MessageType;
    topic = _topic;
    queue_size = _queue_size;
    md5sum = message_traits::md5sum<MessageType>();
    datatype = message_traits::datatype<MessageType>();
    helper = boost::make_shared<SubscriptionCallbackHelperT<P> >(_callback, factory_fn);
  }

  /// For a callback taking const boost::shared_ptr<M const>&.
  template <class M>
  void init(const std::string& _topic, uint32_t _queue_size,
            const boost::function<void(const boost::shared_ptr<M const>&)>& _callback,
            const boost::function<boost::shared_ptr<M>(void)>& factory_fn = DefaultMessageCreator<M>())
  {
    typedef typename ParameterAdapter<M>::Message MessageType;
    topic = _topic;
    queue_size = _queue_size;
    md5sum = message_traits::md5sum<MessageType>();
    datatype = message_traits::datatype<MessageType>();
    helper = boost::make_shared<SubscriptionCallbackHelperT<const boost::shared_ptr<MessageType const>&> >(
        _callback, factory_fn);
  }

  std::string topic;
  uint32_t queue_size;  ///< messages kept for a callback not yet run (0: no limit)
  std::string md5sum;
  std::string datatype;
  SubscriptionCallbackHelperPtr helper;
  CallbackQueueInterface* callback_queue;  ///< 0: the NodeHandle's queue (the global one)
  /// roscpp's per-subscription concurrency; ddes's world allows what the spinner allows.
  bool allow_concurrent_callbacks;
  /// While set, the callback runs only as long as this object lives.
  VoidConstPtr tracked_object;
  TransportHints transport_hints;

  template <class M>
  static SubscribeOptions create(const std::string& topic, uint32_t queue_size,
                                 const boost::function<void(const boost::shared_ptr<M const>&)>& callback,
                                 const VoidConstPtr& tracked_object, CallbackQueueInterface* queue)
  {
    SubscribeOptions ops;
    ops.init<M>(topic, queue_size, callback);
    ops.tracked_object = tracked_object;
    ops.callback_queue = queue;
    return ops;
  }
};

}  // namespace ros

#endif  // ROSCPP_SUBSCRIBE_OPTIONS_H
