// ddes roscpp: the typed half of a service server: ros::ServiceEvent, ros::ServiceSpec and
// ros::ServiceCallbackHelperT (deserialize the request, call the handler, serialize the
// response).
#ifndef ROSCPP_SERVICE_MESSAGE_HELPER_H
#define ROSCPP_SERVICE_MESSAGE_HELPER_H

#include <string>

#include <boost/function.hpp>
#include <boost/make_shared.hpp>
#include <boost/shared_ptr.hpp>

#include <ros/forwards.h>
#include <ros/serialization.h>
#include <ros/service_traits.h>

namespace ros
{

struct ServiceCallbackHelperCallParams
{
  SerializedMessage request;   ///< the request's bytes (no length prefix)
  SerializedMessage response;  ///< filled in: TCPROS's response (ok byte, length, message)
  boost::shared_ptr<M_string> connection_header;
};

template <typename M>
inline boost::shared_ptr<M> defaultServiceCreateFunction()
{
  return boost::make_shared<M>();
}

template <typename MReq, typename MRes>
struct ServiceSpecCallParams
{
  boost::shared_ptr<MReq> request;
  boost::shared_ptr<MRes> response;
  boost::shared_ptr<M_string> connection_header;
};

/// What a handler taking `ros::ServiceEvent<Req, Res>&` receives: the request, the response to
/// fill in, the caller's connection header.
template <typename MReq, typename MRes>
class ServiceEvent
{
public:
  typedef MReq RequestType;
  typedef MRes ResponseType;
  typedef boost::shared_ptr<RequestType> RequestPtr;
  typedef boost::shared_ptr<ResponseType> ResponsePtr;
  typedef boost::function<bool(ServiceEvent<RequestType, ResponseType>&)> CallbackType;

  static bool call(const CallbackType& cb, ServiceSpecCallParams<RequestType, ResponseType>& params)
  {
    ServiceEvent<RequestType, ResponseType> event(params.request, params.response, params.connection_header);
    return cb(event);
  }

  ServiceEvent(const boost::shared_ptr<MReq const>& req, const boost::shared_ptr<MRes>& res,
               const boost::shared_ptr<M_string>& connection_header)
  : request_(req), response_(res), connection_header_(connection_header)
  {}

  const RequestType& getRequest() const { return *request_; }
  ResponseType& getResponse() const { return *response_; }
  M_string& getConnectionHeader() const { return *connection_header_; }
  /// The calling node's name.
  const std::string& getCallerName() const { return (*connection_header_)["callerid"]; }

private:
  boost::shared_ptr<RequestType const> request_;
  boost::shared_ptr<ResponseType> response_;
  boost::shared_ptr<M_string> connection_header_;
};

/// A handler taking (Req&, Res&).
template <typename MReq, typename MRes>
struct ServiceSpec
{
  typedef MReq RequestType;
  typedef MRes ResponseType;
  typedef boost::shared_ptr<RequestType> RequestPtr;
  typedef boost::shared_ptr<ResponseType> ResponsePtr;
  typedef boost::function<bool(RequestType&, ResponseType&)> CallbackType;

  static bool call(const CallbackType& cb, ServiceSpecCallParams<RequestType, ResponseType>& params)
  {
    return cb(*params.request, *params.response);
  }
};

class ServiceCallbackHelper
{
public:
  virtual ~ServiceCallbackHelper() {}
  virtual bool call(ServiceCallbackHelperCallParams& params) = 0;
};
typedef boost::shared_ptr<ServiceCallbackHelper> ServiceCallbackHelperPtr;

template <typename Spec>
class ServiceCallbackHelperT : public ServiceCallbackHelper
{
public:
  typedef typename Spec::RequestType RequestType;
  typedef typename Spec::ResponseType ResponseType;
  typedef typename Spec::RequestPtr RequestPtr;
  typedef typename Spec::ResponsePtr ResponsePtr;
  typedef typename Spec::CallbackType Callback;
  typedef boost::function<RequestPtr()> ReqCreateFunction;
  typedef boost::function<ResponsePtr()> ResCreateFunction;

  ServiceCallbackHelperT(const Callback& callback,
                         const ReqCreateFunction& create_req =
                             static_cast<RequestPtr (*)()>(defaultServiceCreateFunction<RequestType>),
                         const ResCreateFunction& create_res =
                             static_cast<ResponsePtr (*)()>(defaultServiceCreateFunction<ResponseType>))
  : callback_(callback), create_req_(create_req), create_res_(create_res)
  {}

  virtual bool call(ServiceCallbackHelperCallParams& params)
  {
    namespace ser = serialization;
    RequestPtr req(create_req_());
    ResponsePtr res(create_res_());
    ser::deserializeMessage(params.request, *req);
    ServiceSpecCallParams<RequestType, ResponseType> call_params;
    call_params.request = req;
    call_params.response = res;
    call_params.connection_header = params.connection_header;
    bool ok = Spec::call(callback_, call_params);
    params.response = ser::serializeServiceResponse(ok, *res);
    return ok;
  }

private:
  Callback callback_;
  ReqCreateFunction create_req_;
  ResCreateFunction create_res_;
};

}  // namespace ros

#endif  // ROSCPP_SERVICE_MESSAGE_HELPER_H
