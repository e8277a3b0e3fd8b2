// ddes roscpp: ros::SubscriptionCallbackHelper, a subscription's typed half: it deserializes
// the bytes the world delivers and calls the user's callback with the parameter it asked for.
#ifndef ROSCPP_SUBSCRIPTION_CALLBACK_HELPER_H
#define ROSCPP_SUBSCRIPTION_CALLBACK_HELPER_H

#include <typeinfo>

#include <boost/function.hpp>
#include <boost/shared_ptr.hpp>

#include <ros/forwards.h>
#include <ros/message_event.h>
#include <ros/message_traits.h>
#include <ros/parameter_adapter.h>
#include <ros/serialization.h>

namespace ros
{

struct SubscriptionCallbackHelperDeserializeParams
{
  uint8_t* buffer;
  uint32_t length;
  boost::shared_ptr<M_string> connection_header;
};

struct SubscriptionCallbackHelperCallParams
{
  MessageEvent<void const> event;
};

class SubscriptionCallbackHelper
{
public:
  virtual ~SubscriptionCallbackHelper() {}
  virtual VoidConstPtr deserialize(const SubscriptionCallbackHelperDeserializeParams&) = 0;
  virtual void call(SubscriptionCallbackHelperCallParams& params) = 0;
  virtual const std::type_info& getTypeInfo() = 0;
  virtual bool isConst() = 0;
  virtual bool hasHeader() = 0;
};
typedef boost::shared_ptr<SubscriptionCallbackHelper> SubscriptionCallbackHelperPtr;

/// The helper for a callback taking P (see ros::ParameterAdapter).
template <typename P, typename Enabled = void>
class SubscriptionCallbackHelperT : public SubscriptionCallbackHelper
{
public:
  typedef ParameterAdapter<P> Adapter;
  typedef typename ParameterAdapter<P>::Message NonConstType;
  typedef typename ParameterAdapter<P>::Event Event;
  typedef typename std::add_const<NonConstType>::type ConstType;
  typedef boost::shared_ptr<NonConstType> NonConstTypePtr;
  typedef boost::shared_ptr<ConstType> ConstTypePtr;

  static const bool is_const = ParameterAdapter<P>::is_const;

  typedef boost::function<void(typename Adapter::Parameter)> Callback;
  typedef boost::function<NonConstTypePtr()> CreateFunction;

  SubscriptionCallbackHelperT(const Callback& callback,
                              const CreateFunction& create = DefaultMessageCreator<NonConstType>())
  : callback_(callback), create_(create)
  {}

  void setCreateFunction(const CreateFunction& create) { create_ = create; }

  virtual bool hasHeader() { return message_traits::hasHeader<typename ParameterAdapter<P>::Message>(); }

  virtual VoidConstPtr deserialize(const SubscriptionCallbackHelperDeserializeParams& params)
  {
    namespace ser = serialization;
    NonConstTypePtr msg = create_();
    if (!msg)
      return VoidConstPtr();
    ser::PreDeserializeParams<NonConstType> predes_params;
    predes_params.message = msg;
    predes_params.connection_header = params.connection_header;
    ser::PreDeserialize<NonConstType>::notify(predes_params);
    ser::IStream stream(params.buffer, params.length);
    ser::deserialize(stream, *msg);
    return VoidConstPtr(msg);
  }

  virtual void call(SubscriptionCallbackHelperCallParams& params)
  {
    Event event(params.event, create_);
    callback_(ParameterAdapter<P>::getParameter(event));
  }

  virtual const std::type_info& getTypeInfo() { return typeid(NonConstType); }
  virtual bool isConst() { return ParameterAdapter<P>::is_const; }

private:
  Callback callback_;
  CreateFunction create_;
};

}  // namespace ros

#endif  // ROSCPP_SUBSCRIPTION_CALLBACK_HELPER_H
