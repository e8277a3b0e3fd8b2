// ddes roscpp: ros::service, one-off calls and waiting for a service.
#ifndef ROSCPP_SERVICE_H
#define ROSCPP_SERVICE_H

#include <string>

#include <ros/common.h>
#include <ros/forwards.h>
#include <ros/names.h>
#include <ros/node_handle.h>
#include <ros/service_client_options.h>
#include <ros/service_traits.h>

namespace ros
{
namespace service
{

template <class MReq, class MRes>
bool call(const std::string& service_name, MReq& req, MRes& res)
{
  namespace st = service_traits;
  NodeHandle nh;
  ServiceClientOptions ops(ros::names::resolve(service_name), st::md5sum(req), false, M_string());
  ops.datatype = st::datatype(req);
  ServiceClient client = nh.serviceClient(ops);
  return client.call(req, res);
}

template <class Service>
bool call(const std::string& service_name, Service& service)
{
  namespace st = service_traits;
  NodeHandle nh;
  ServiceClientOptions ops(ros::names::resolve(service_name), st::md5sum(service), false, M_string());
  ops.datatype = st::datatype(service);
  ServiceClient client = nh.serviceClient(ops);
  return client.call(service.request, service.response);
}

/// Waits until the service is advertised (roscpp's poll: every 0.02 s of ROS time, logging
/// once that it waits and once that it is there); `timeout` in milliseconds, -1 forever.
bool waitForService(const std::string& service_name, int32_t timeout);
bool waitForService(const std::string& service_name, ros::Duration timeout = ros::Duration(-1));
/// Whether the service is advertised now.
bool exists(const std::string& service_name, bool print_failure_reason);

template <class MReq, class MRes>
ServiceClient createClient(const std::string& service_name, bool persistent = false,
                           const M_string& header_values = M_string())
{
  NodeHandle nh;
  return nh.template serviceClient<MReq, MRes>(ros::names::resolve(service_name), persistent, header_values);
}

template <class Service>
ServiceClient createClient(const std::string& service_name, bool persistent = false,
                           const M_string& header_values = M_string())
{
  NodeHandle nh;
  return nh.template serviceClient<Service>(ros::names::resolve(service_name), persistent, header_values);
}

}  // namespace service
}  // namespace ros

#endif  // ROSCPP_SERVICE_H
