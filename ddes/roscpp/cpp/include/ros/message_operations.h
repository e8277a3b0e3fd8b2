// ddes roscpp: ros::message_operations::Printer, the text operator<< prints for a message.
//
// A generated header specialises Printer for its message: "field: value" lines, a nested
// message's fields indented two spaces under "field: ", an array as "field[]" then one
// "  field[i]: value" line per element (gencpp's format).  This primary template prints a
// value with operator<< and a newline; int8/uint8 print as numbers, not characters.
#ifndef ROSLIB_MESSAGE_OPERATIONS_H
#define ROSLIB_MESSAGE_OPERATIONS_H

#include <cstdint>
#include <ostream>
#include <string>

namespace ros
{
namespace message_operations
{

template <typename M>
struct Printer
{
  template <typename Stream>
  static void stream(Stream& s, const std::string& indent, const M& value)
  {
    (void)indent;
    s << value << "\n";
  }
};

template <>
struct Printer<int8_t>
{
  template <typename Stream>
  static void stream(Stream& s, const std::string& indent, int8_t value)
  {
    (void)indent;
    s << static_cast<int32_t>(value) << "\n";
  }
};

template <>
struct Printer<uint8_t>
{
  template <typename Stream>
  static void stream(Stream& s, const std::string& indent, uint8_t value)
  {
    (void)indent;
    s << static_cast<uint32_t>(value) << "\n";
  }
};

}  // namespace message_operations
}  // namespace ros

#endif  // ROSLIB_MESSAGE_OPERATIONS_H
