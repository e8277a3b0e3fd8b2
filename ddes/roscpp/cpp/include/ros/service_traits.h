// ddes roscpp: ros::service_traits, the md5 sum and type name of a service.
//
// A generated pkg/Srv.h specialises MD5Sum and DataType for the service and for its
// Request and Response types (whose service traits are the service's).
#ifndef ROSCPP_SERVICE_TRAITS_H
#define ROSCPP_SERVICE_TRAITS_H

#include <type_traits>

namespace ros
{
namespace service_traits
{

/// The service's md5 sum (of the request's md5 text then the response's).
template <typename M>
struct MD5Sum
{
  static const char* value() { return M::__s_getServerMD5Sum().c_str(); }
  static const char* value(const M& m) { return m.__getServerMD5Sum().c_str(); }
};

/// The service's type name, "pkg/Srv".
template <typename M>
struct DataType
{
  static const char* value() { return M::__s_getServiceDataType().c_str(); }
  static const char* value(const M& m) { return m.__getServiceDataType().c_str(); }
};

namespace detail
{
template <typename M>
using Bare = typename std::remove_const<typename std::remove_reference<M>::type>::type;
}  // namespace detail

template <typename M> inline const char* md5sum() { return MD5Sum<detail::Bare<M> >::value(); }
template <typename M> inline const char* datatype() { return DataType<detail::Bare<M> >::value(); }
template <typename M> inline const char* md5sum(const M& m) { return MD5Sum<detail::Bare<M> >::value(m); }
template <typename M> inline const char* datatype(const M& m) { return DataType<detail::Bare<M> >::value(m); }

}  // namespace service_traits
}  // namespace ros

#endif  // ROSCPP_SERVICE_TRAITS_H
