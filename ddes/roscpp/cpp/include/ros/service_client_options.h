// ddes roscpp: ros::ServiceClientOptions, everything NodeHandle::serviceClient needs.
#ifndef ROSCPP_SERVICE_CLIENT_OPTIONS_H
#define ROSCPP_SERVICE_CLIENT_OPTIONS_H

#include <string>

#include <ros/forwards.h>
#include <ros/service_traits.h>

namespace ros
{

struct ServiceClientOptions
{
  ServiceClientOptions() : persistent(false) {}

  ServiceClientOptions(const std::string& _service, const std::string& _md5sum, bool _persistent,
                       const M_string& _header)
  : service(_service), md5sum(_md5sum), persistent(_persistent), header(_header)
  {}

  template <class MReq, class MRes>
  void init(const std::string& _service, bool _persistent, const M_string& _header)
  {
    namespace st = service_traits;
    service = _service;
    md5sum = st::md5sum<MReq>();
    datatype = st::datatype<MReq>();
    persistent = _persistent;
    header = _header;
  }

  template <class Service>
  void init(const std::string& _service, bool _persistent, const M_string& _header)
  {
    namespace st = service_traits;
    service = _service;
    md5sum = st::md5sum<Service>();
    datatype = st::datatype<Service>();
    persistent = _persistent;
    header = _header;
  }

  std::string service;
  std::string md5sum;
  bool persistent;  ///< keep one connection for every call (it fails once the server goes)
  M_string header;  ///< extra connection-header fields (kept; ddes's world does not send them)
  /// ddes: the service type ("pkg/Srv") when the options were made from a type; otherwise the
  /// typed call() names it.
  std::string datatype;
};

}  // namespace ros

#endif  // ROSCPP_SERVICE_CLIENT_OPTIONS_H
