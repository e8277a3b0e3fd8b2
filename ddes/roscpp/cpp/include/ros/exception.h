// ddes roscpp: ros::Exception, the base of roscpp's exceptions.
#ifndef ROSLIB_EXCEPTION_H
#define ROSLIB_EXCEPTION_H

#include <stdexcept>
#include <string>

namespace ros
{

/// Base of every exception roscpp (and ddes's roscpp) throws; a std::runtime_error.
class Exception : public std::runtime_error
{
public:
  Exception(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace ros

#endif  // ROSLIB_EXCEPTION_H
