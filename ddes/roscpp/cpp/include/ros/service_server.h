// ddes roscpp: ros::ServiceServer, a handle on an advertised service.  Copies share it; it is
// withdrawn (UNADVERTISE_SERVICE) by shutdown() or when the last copy is destroyed.
#ifndef ROSCPP_SERVICE_HANDLE_H
#define ROSCPP_SERVICE_HANDLE_H

#include <string>
#include <vector>

#include <boost/shared_ptr.hpp>

#include <ros/common.h>
#include <ros/forwards.h>

namespace ros
{

namespace ddes
{
class ServiceServerImpl;
}

class ServiceServer
{
public:
  ServiceServer() {}
  ServiceServer(const ServiceServer& rhs);
  ~ServiceServer();
  ServiceServer& operator=(const ServiceServer& other) = default;

  void shutdown();
  /// The resolved service name.
  std::string getService() const;

  operator void*() const { return (impl_ && isValidImpl()) ? reinterpret_cast<void*>(1) : static_cast<void*>(0); }

  bool operator<(const ServiceServer& rhs) const { return impl_ < rhs.impl_; }
  bool operator==(const ServiceServer& rhs) const { return impl_ == rhs.impl_; }
  bool operator!=(const ServiceServer& rhs) const { return impl_ != rhs.impl_; }

private:
  explicit ServiceServer(const boost::shared_ptr<ddes::ServiceServerImpl>& impl);
  bool isValidImpl() const;

  boost::shared_ptr<ddes::ServiceServerImpl> impl_;

  friend class NodeHandle;
};
typedef std::vector<ServiceServer> V_ServiceServer;

}  // namespace ros

#endif  // ROSCPP_SERVICE_HANDLE_H
