// ddes roscpp: ros::ParameterAdapter<P>, how a subscription callback's parameter type P is
// made from the received event.  P may be:
//   const boost::shared_ptr<M const>&, const boost::shared_ptr<M>&, boost::shared_ptr<M const>,
//   boost::shared_ptr<M>, const M&, M, const ros::MessageEvent<M const>&,
//   const ros::MessageEvent<M>&
// (the non-const forms get a copy of the message, as in roscpp).
#ifndef ROSCPP_PARAMETER_ADAPTER_H
#define ROSCPP_PARAMETER_ADAPTER_H

#include <type_traits>

#include <ros/forwards.h>
#include <ros/message_event.h>

namespace ros
{

template <typename M>
struct ParameterAdapter
{
  typedef typename std::remove_reference<typename std::remove_const<M>::type>::type Message;
  typedef ros::MessageEvent<Message const> Event;
  typedef M Parameter;
  static const bool is_const = true;

  static Parameter getParameter(const Event& event) { return *event.getMessage(); }
};

template <typename M>
struct ParameterAdapter<const boost::shared_ptr<M const>&>
{
  typedef typename std::remove_reference<typename std::remove_const<M>::type>::type Message;
  typedef ros::MessageEvent<Message const> Event;
  typedef const boost::shared_ptr<Message const> Parameter;
  static const bool is_const = true;

  static Parameter getParameter(const Event& event) { return event.getMessage(); }
};

template <typename M>
struct ParameterAdapter<const boost::shared_ptr<M>&>
{
  typedef typename std::remove_reference<typename std::remove_const<M>::type>::type Message;
  typedef ros::MessageEvent<Message const> Event;
  typedef boost::shared_ptr<Message> Parameter;
  static const bool is_const = false;

  static Parameter getParameter(const Event& event) { return ros::MessageEvent<Message>(event).getMessage(); }
};

template <typename M>
struct ParameterAdapter<const M&>
{
  typedef typename std::remove_reference<typename std::remove_const<M>::type>::type Message;
  typedef ros::MessageEvent<Message const> Event;
  typedef const M& Parameter;
  static const bool is_const = true;

  static Parameter getParameter(const Event& event) { return *event.getMessage(); }
};

template <typename M>
struct ParameterAdapter<boost::shared_ptr<M const> >
{
  typedef typename std::remove_reference<typename std::remove_const<M>::type>::type Message;
  typedef ros::MessageEvent<Message const> Event;
  typedef boost::shared_ptr<Message const> Parameter;
  static const bool is_const = true;

  static Parameter getParameter(const Event& event) { return event.getMessage(); }
};

template <typename M>
struct ParameterAdapter<boost::shared_ptr<M> >
{
  typedef typename std::remove_reference<typename std::remove_const<M>::type>::type Message;
  typedef ros::MessageEvent<Message const> Event;
  typedef boost::shared_ptr<Message> Parameter;
  static const bool is_const = false;

  static Parameter getParameter(const Event& event) { return ros::MessageEvent<Message>(event).getMessage(); }
};

template <typename M>
struct ParameterAdapter<const ros::MessageEvent<M const>&>
{
  typedef typename std::remove_reference<typename std::remove_const<M>::type>::type Message;
  typedef ros::MessageEvent<Message const> Event;
  typedef const ros::MessageEvent<Message const>& Parameter;
  static const bool is_const = true;

  static Parameter getParameter(const Event& event) { return event; }
};

template <typename M>
struct ParameterAdapter<const ros::MessageEvent<M>&>
{
  typedef typename std::remove_reference<typename std::remove_const<M>::type>::type Message;
  typedef ros::MessageEvent<Message const> Event;
  typedef ros::MessageEvent<Message> Parameter;
  static const bool is_const = false;

  static Parameter getParameter(const Event& event) { return ros::MessageEvent<Message>(event); }
};

}  // namespace ros

#endif  // ROSCPP_PARAMETER_ADAPTER_H
