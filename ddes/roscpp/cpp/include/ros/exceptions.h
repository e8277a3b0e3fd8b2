// ddes roscpp: the exceptions roscpp throws (all are ros::Exception, a std::runtime_error).
#ifndef ROSCPP_EXCEPTIONS_H
#define ROSCPP_EXCEPTIONS_H

#include <string>

#include <ros/exception.h>

namespace ros
{

/// A name that is not a valid graph resource name (or a ~ name given to a NodeHandle method).
class InvalidNameException : public ros::Exception
{
public:
  InvalidNameException(const std::string& msg) : Exception(msg) {}
};

/// A node name that ros::init refuses.
class InvalidNodeNameException : public ros::Exception
{
public:
  InvalidNodeNameException(const std::string& name, const std::string& reason)
  : Exception("Invalid node name [" + name + "]: " + reason)
  {}
};

/// A topic advertised or subscribed with a type that conflicts with what the node has on it.
class ConflictingSubscriptionException : public ros::Exception
{
public:
  ConflictingSubscriptionException(const std::string& msg) : Exception(msg) {}
};

class InvalidParameterException : public ros::Exception
{
public:
  InvalidParameterException(const std::string& msg) : Exception(msg) {}
};

class InvalidPortException : public ros::Exception
{
public:
  InvalidPortException(const std::string& msg) : Exception(msg) {}
};

}  // namespace ros

#endif  // ROSCPP_EXCEPTIONS_H
