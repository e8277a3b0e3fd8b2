// ddes roscpp: ros::message_traits, what a message type says about itself.
//
// gencpp headers specialise IsMessage, IsFixedSize, HasHeader, MD5Sum, DataType and Definition
// for each message; the helpers md5sum<M>(), datatype<M>(), definition<M>(), hasHeader<M>(),
// isFixedSize<M>(), isSimple<M>(), header(m), frameId(m) and timeStamp(m) read them.
#ifndef ROSLIB_MESSAGE_TRAITS_H
#define ROSLIB_MESSAGE_TRAITS_H

#include <string>
#include <type_traits>

#include <ros/message_forward.h>
#include <ros/time.h>

namespace std_msgs
{
ROS_DECLARE_MESSAGE(Header)
}

/// Traits of a hand-written message class (not generated): its md5, type and definition.
#define ROS_IMPLEMENT_SIMPLE_TOPIC_TRAITS(msg, md5sum, datatype, definition) \
  namespace ros \
  { \
  namespace message_traits \
  { \
  template <> struct MD5Sum<msg> \
  { \
    static const char* value() { return md5sum; } \
    static const char* value(const msg&) { return value(); } \
  }; \
  template <> struct DataType<msg> \
  { \
    static const char* value() { return datatype; } \
    static const char* value(const msg&) { return value(); } \
  }; \
  template <> struct Definition<msg> \
  { \
    static const char* value() { return definition; } \
    static const char* value(const msg&) { return value(); } \
  }; \
  } \
  }

namespace ros
{
namespace message_traits
{

/// A true trait (also a std::true_type, so it works with <type_traits>).
struct TrueType : std::true_type
{
  typedef TrueType type;
};

/// A false trait (also a std::false_type).
struct FalseType : std::false_type
{
  typedef FalseType type;
};

/// Its memory is its wire form (a primitive, ros::Time, ros::Duration): arrays are memcpy'd.
template <typename M> struct IsSimple : public FalseType {};
/// Every value has the same serialized length.
template <typename M> struct IsFixedSize : public FalseType {};
/// Its first field is `std_msgs/Header header`.
template <typename M> struct HasHeader : public FalseType {};
/// A ROS message type.
template <typename M> struct IsMessage : public FalseType {};

/// The md5 sum of a message type (generated headers specialise it).
template <typename M>
struct MD5Sum
{
  static const char* value() { return M::__s_getMD5Sum().c_str(); }
  static const char* value(const M& m) { return m.__getMD5Sum().c_str(); }
};

/// The type name, "pkg/Type".
template <typename M>
struct DataType
{
  static const char* value() { return M::__s_getDataType().c_str(); }
  static const char* value(const M& m) { return m.__getDataType().c_str(); }
};

/// The full definition text (the type's, then each dependency's after a line of '=').
template <typename M>
struct Definition
{
  static const char* value() { return M::__s_getMessageDefinition().c_str(); }
  static const char* value(const M& m) { return m.__getMessageDefinition().c_str(); }
};

/// A pointer to the message's header, or null if it has none.
template <typename M, typename Enable = void>
struct Header
{
  static std_msgs::Header* pointer(M& m) { (void)m; return 0; }
  static std_msgs::Header const* pointer(const M& m) { (void)m; return 0; }
};

template <typename M>
struct Header<M, typename std::enable_if<HasHeader<M>::value>::type>
{
  static std_msgs::Header* pointer(M& m) { return &m.header; }
  static std_msgs::Header const* pointer(const M& m) { return &m.header; }
};

/// A pointer to header.frame_id, or null.
template <typename M, typename Enable = void>
struct FrameId
{
  static std::string* pointer(M& m) { (void)m; return 0; }
  static std::string const* pointer(const M& m) { (void)m; return 0; }
};

template <typename M>
struct FrameId<M, typename std::enable_if<HasHeader<M>::value>::type>
{
  static std::string* pointer(M& m) { return &m.header.frame_id; }
  static std::string const* pointer(const M& m) { return &m.header.frame_id; }
  static std::string value(const M& m) { return m.header.frame_id; }
};

/// A pointer to header.stamp, or null.
template <typename M, typename Enable = void>
struct TimeStamp
{
  static ros::Time* pointer(M& m) { (void)m; return 0; }
  static ros::Time const* pointer(const M& m) { (void)m; return 0; }
};

template <typename M>
struct TimeStamp<M, typename std::enable_if<HasHeader<M>::value>::type>
{
  static ros::Time* pointer(typename std::remove_const<M>::type& m) { return &m.header.stamp; }
  static ros::Time const* pointer(const M& m) { return &m.header.stamp; }
  static ros::Time value(const M& m) { return m.header.stamp; }
};

namespace detail
{
template <typename M>
using Bare = typename std::remove_const<typename std::remove_reference<M>::type>::type;
}  // namespace detail

template <typename M> inline const char* md5sum() { return MD5Sum<detail::Bare<M> >::value(); }
template <typename M> inline const char* datatype() { return DataType<detail::Bare<M> >::value(); }
template <typename M> inline const char* definition() { return Definition<detail::Bare<M> >::value(); }
template <typename M> inline const char* md5sum(const M& m) { return MD5Sum<detail::Bare<M> >::value(m); }
template <typename M> inline const char* datatype(const M& m) { return DataType<detail::Bare<M> >::value(m); }
template <typename M> inline const char* definition(const M& m) { return Definition<detail::Bare<M> >::value(m); }

template <typename M> inline std_msgs::Header* header(M& m) { return Header<detail::Bare<M> >::pointer(m); }
template <typename M> inline std_msgs::Header const* header(const M& m) { return Header<detail::Bare<M> >::pointer(m); }
template <typename M> inline std::string* frameId(M& m) { return FrameId<detail::Bare<M> >::pointer(m); }
template <typename M> inline std::string const* frameId(const M& m) { return FrameId<detail::Bare<M> >::pointer(m); }
template <typename M> inline ros::Time* timeStamp(M& m) { return TimeStamp<detail::Bare<M> >::pointer(m); }
template <typename M> inline ros::Time const* timeStamp(const M& m) { return TimeStamp<detail::Bare<M> >::pointer(m); }

template <typename M> inline bool isSimple() { return IsSimple<detail::Bare<M> >::value; }
template <typename M> inline bool isFixedSize() { return IsFixedSize<detail::Bare<M> >::value; }
template <typename M> inline bool hasHeader() { return HasHeader<detail::Bare<M> >::value; }

}  // namespace message_traits
}  // namespace ros

#endif  // ROSLIB_MESSAGE_TRAITS_H
