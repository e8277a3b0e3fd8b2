// ddes roscpp: ros::service (exists, waitForService) and ros::topic::waitForMessage.
#include "ddes_core.h"

#include <ros/console.h>
#include <ros/init.h>
#include <ros/node_handle.h>
#include <ros/service.h>
#include <ros/topic.h>

namespace ros
{

namespace service
{

/// SERVICE_EXISTS for `name` read in namespace `ns`; roscpp's "waiting" line when asked.
bool existsIn(const std::string& ns, const std::string& name, bool print_failure_reason)
{
  ddes::requireInit("looking up a service");
  if (!ddes::live())
    return false;
  ddes::Writer w = ddes::Writer::request();
  w.str(ns).str(name);
  bool exists = false;
  try
  {
    exists = ddes::request(ddes::SERVICE_EXISTS, w).u8() != 0;
  }
  catch (ddes::ReplyError&)
  {
    exists = false;
  }
  if (!exists && print_failure_reason)
    ROS_INFO("waitForService: Service [%s] has not been advertised, waiting...",
             ddes::resolveRemote(ns, name).c_str());
  return exists;
}

/// roscpp's waitForService: poll every 0.02 s of ROS time until the service is there, the
/// node shuts down or `timeout` (wall time; negative: none) has passed.
bool waitForServiceIn(const std::string& ns, const std::string& name, ros::Duration timeout)
{
  ddes::requireInit("waiting for a service");
  const WallTime start = WallTime::now();
  bool printed = false;
  bool result = false;
  while (ros::ok())
  {
    if (existsIn(ns, name, !printed))
    {
      result = true;
      break;
    }
    printed = true;
    if (timeout >= Duration(0))
    {
      const WallTime current = WallTime::now();
      if (static_cast<int64_t>((current - start).toNSec()) >= timeout.toNSec())
        return false;
    }
    Duration(0.02).sleep();
  }
  if (printed && ros::ok())
    ROS_INFO("waitForService: Service [%s] is now available.", ddes::resolveRemote(ns, name).c_str());
  return result;
}

bool waitForService(const std::string& service_name, int32_t timeout)
{
  return waitForService(service_name, ros::Duration(timeout / 1000.0));
}

bool waitForService(const std::string& service_name, ros::Duration timeout)
{
  ddes::requireInit("waiting for a service");
  return waitForServiceIn(ddes::state().ns, ddes::nodeRelative(service_name), timeout);
}

bool exists(const std::string& service_name, bool print_failure_reason)
{
  ddes::requireInit("looking up a service");
  return existsIn(ddes::state().ns, ddes::nodeRelative(service_name), print_failure_reason);
}

}  // namespace service

namespace topic
{
namespace ddes_detail
{

bool waitForMessageBytes(const std::string& topic, NodeHandle& nh, ros::Duration timeout, const char* datatype,
                         const char* md5sum, std::vector<uint8_t>& bytes)
{
  nh.resolveName(topic, false);  // roscpp's checks (InvalidNameException), nothing asked
  if (!ddes::live() || !nh.ok())
    return false;
  ddes::Writer w = ddes::Writer::request();
  w.str(nh.getNamespace())
      .str(topic)
      .str(datatype)
      .str(md5sum)
      .i64(timeout.isZero() ? -1 : static_cast<int64_t>(timeout.toNSec()));
  try
  {
    ddes::Reader r = ddes::blocking(ddes::WAIT_FOR_MESSAGE, w);
    const bool got = r.u8() != 0;
    uint32_t n = 0;
    const uint8_t* data = r.blob(n);
    if (!got)
      return false;
    bytes.assign(data, data + n);
    return true;
  }
  catch (ddes::ReplyError& e)
  {
    ROS_ERROR("%s", e.what());
    return false;
  }
}

}  // namespace ddes_detail
}  // namespace topic

}  // namespace ros
