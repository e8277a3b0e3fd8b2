// ddes roscpp: ros::SerializedMessage, a message's bytes behind a u32 length prefix.
#ifndef ROSLIB_SERIALIZED_MESSAGE_H
#define ROSLIB_SERIALIZED_MESSAGE_H

#include <cstddef>
#include <cstdint>
#include <typeinfo>

#include <boost/shared_array.hpp>
#include <boost/shared_ptr.hpp>

namespace ros
{

/// buf holds num_bytes bytes; the message itself starts at message_start (after the
/// 4-byte length serializeMessage writes first).
class SerializedMessage
{
public:
  boost::shared_array<uint8_t> buf;
  size_t num_bytes;
  uint8_t* message_start;

  boost::shared_ptr<void const> message;
  const std::type_info* type_info;

  SerializedMessage() : buf(boost::shared_array<uint8_t>()), num_bytes(0), message_start(0), type_info(0) {}

  SerializedMessage(boost::shared_array<uint8_t> _buf, size_t _num_bytes)
  : buf(_buf), num_bytes(_num_bytes), message_start(_buf ? _buf.get() : 0), type_info(0)
  {}
};

}  // namespace ros

#endif  // ROSLIB_SERIALIZED_MESSAGE_H
