// ddes roscpp: ros::MessageEvent<M>, a received message with its connection header and receipt
// time (what a callback taking `const ros::MessageEvent<M const>&` receives).
#ifndef ROSCPP_MESSAGE_EVENT_H
#define ROSCPP_MESSAGE_EVENT_H

#include <string>
#include <type_traits>

#include <boost/function.hpp>
#include <boost/make_shared.hpp>
#include <boost/shared_ptr.hpp>

#include <ros/datatypes.h>
#include <ros/macros.h>
#include <ros/message_traits.h>
#include <ros/time.h>

namespace ros
{

/// Makes an empty message (the default factory of subscriptions).
template <typename M>
struct DefaultMessageCreator
{
  boost::shared_ptr<M> operator()() { return boost::make_shared<M>(); }
};

template <typename M>
ROS_DEPRECATED inline boost::shared_ptr<M> defaultMessageCreateFunction()
{
  return DefaultMessageCreator<M>()();
}

template <typename M>
class MessageEvent
{
public:
  typedef typename std::add_const<M>::type ConstMessage;
  typedef typename std::remove_const<M>::type Message;
  typedef boost::shared_ptr<Message> MessagePtr;
  typedef boost::shared_ptr<ConstMessage> ConstMessagePtr;
  typedef boost::function<MessagePtr()> CreateFunction;

  MessageEvent() : nonconst_need_copy_(true) {}

  MessageEvent(const MessageEvent<Message>& rhs) { *this = rhs; }
  MessageEvent(const MessageEvent<ConstMessage>& rhs) { *this = rhs; }

  MessageEvent(const MessageEvent<Message>& rhs, bool nonconst_need_copy)
  {
    *this = rhs;
    nonconst_need_copy_ = nonconst_need_copy;
  }
  MessageEvent(const MessageEvent<ConstMessage>& rhs, bool nonconst_need_copy)
  {
    *this = rhs;
    nonconst_need_copy_ = nonconst_need_copy;
  }

  /// From an untyped event (the message is of type Message); `create` makes copies.
  MessageEvent(const MessageEvent<void const>& rhs, const CreateFunction& create)
  {
    init(boost::const_pointer_cast<Message>(boost::static_pointer_cast<ConstMessage>(rhs.getMessage())),
         rhs.getConnectionHeaderPtr(), rhs.getReceiptTime(), rhs.nonConstWillCopy(), create);
  }

  /// A message received now, with no connection header.
  MessageEvent(const ConstMessagePtr& message)
  {
    init(message, boost::shared_ptr<M_string>(), ros::Time::now(), true, ros::DefaultMessageCreator<Message>());
  }

  MessageEvent(const ConstMessagePtr& message, const boost::shared_ptr<M_string>& connection_header,
               ros::Time receipt_time)
  {
    init(message, connection_header, receipt_time, true, ros::DefaultMessageCreator<Message>());
  }

  MessageEvent(const ConstMessagePtr& message, ros::Time receipt_time)
  {
    init(message, boost::shared_ptr<M_string>(), receipt_time, true, ros::DefaultMessageCreator<Message>());
  }

  MessageEvent(const ConstMessagePtr& message, const boost::shared_ptr<M_string>& connection_header,
               ros::Time receipt_time, bool nonconst_need_copy, const CreateFunction& create)
  {
    init(message, connection_header, receipt_time, nonconst_need_copy, create);
  }

  void init(const ConstMessagePtr& message, const boost::shared_ptr<M_string>& connection_header,
            ros::Time receipt_time, bool nonconst_need_copy, const CreateFunction& create)
  {
    message_ = message;
    connection_header_ = connection_header;
    receipt_time_ = receipt_time;
    nonconst_need_copy_ = nonconst_need_copy;
    create_ = create;
  }

  void operator=(const MessageEvent<Message>& rhs)
  {
    init(boost::static_pointer_cast<Message>(rhs.getMessage()), rhs.getConnectionHeaderPtr(),
         rhs.getReceiptTime(), rhs.nonConstWillCopy(), rhs.getMessageFactory());
    message_copy_.reset();
  }

  void operator=(const MessageEvent<ConstMessage>& rhs)
  {
    init(boost::const_pointer_cast<Message>(boost::static_pointer_cast<ConstMessage>(rhs.getMessage())),
         rhs.getConnectionHeaderPtr(), rhs.getReceiptTime(), rhs.nonConstWillCopy(), rhs.getMessageFactory());
    message_copy_.reset();
  }

  /// The message; for a non-const M that must not share it, a copy (made once).
  boost::shared_ptr<M> getMessage() const { return copyMessageIfNecessary(std::is_void<Message>()); }

  const boost::shared_ptr<ConstMessage>& getConstMessage() const { return message_; }
  M_string& getConnectionHeader() const { return *connection_header_; }
  const boost::shared_ptr<M_string>& getConnectionHeaderPtr() const { return connection_header_; }

  /// The publishing node's name ("unknown_publisher" without a connection header).
  const std::string& getPublisherName() const
  {
    return connection_header_ ? (*connection_header_)["callerid"] : s_unknown_publisher_string_;
  }

  ros::Time getReceiptTime() const { return receipt_time_; }

  bool nonConstWillCopy() const { return nonconst_need_copy_; }
  bool getMessageWillCopy() const { return !std::is_const<M>::value && nonconst_need_copy_; }

  bool operator<(const MessageEvent<M>& rhs)
  {
    if (message_ != rhs.message_)
      return message_ < rhs.message_;
    if (receipt_time_ != rhs.receipt_time_)
      return receipt_time_ < rhs.receipt_time_;
    return nonconst_need_copy_ < rhs.nonconst_need_copy_;
  }

  bool operator==(const MessageEvent<M>& rhs)
  {
    return message_ == rhs.message_ && receipt_time_ == rhs.receipt_time_ &&
           nonconst_need_copy_ == rhs.nonconst_need_copy_;
  }

  bool operator!=(const MessageEvent<M>& rhs) { return !(*this == rhs); }

  const CreateFunction& getMessageFactory() const { return create_; }

private:
  // (C++11: chosen by overload rather than if constexpr, as packages may compile as C++11)
  boost::shared_ptr<M> copyMessageIfNecessary(std::true_type) const
  {
    return boost::const_pointer_cast<Message>(message_);
  }

  boost::shared_ptr<M> copyMessageIfNecessary(std::false_type) const
  {
    if (std::is_const<M>::value || !nonconst_need_copy_)
      return boost::const_pointer_cast<Message>(message_);
    if (!message_copy_)
    {
      message_copy_ = create_ ? create_() : boost::make_shared<Message>();
      *message_copy_ = *message_;
    }
    return message_copy_;
  }

  ConstMessagePtr message_;
  mutable MessagePtr message_copy_;
  boost::shared_ptr<M_string> connection_header_;
  ros::Time receipt_time_;
  bool nonconst_need_copy_;
  CreateFunction create_;

  static const std::string s_unknown_publisher_string_;
};

template <typename M>
const std::string MessageEvent<M>::s_unknown_publisher_string_("unknown_publisher");

}  // namespace ros

#endif  // ROSCPP_MESSAGE_EVENT_H
