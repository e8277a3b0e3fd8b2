// ddes roscpp: ros::NodeHandle, the node's namespace and the way to topics, services,
// parameters and timers.
//
// Names given to a NodeHandle are resolved in its namespace and remapped by the world
// (docs/external-nodes.md); a "~name" is refused with roscpp's InvalidNameException (make a
// NodeHandle("~") instead).  The first NodeHandle starts the node (ros::start); when the last
// one is destroyed the node stops (ros::ok() is false until a new NodeHandle starts it), as
// in roscpp.  shutdown() ends every publisher, subscriber, service and client made through
// this handle.
#ifndef ROSCPP_NODE_HANDLE_H
#define ROSCPP_NODE_HANDLE_H

#include <map>
#include <string>
#include <vector>

#include <boost/bind/bind.hpp>

#include <ros/advertise_options.h>
#include <ros/advertise_service_options.h>
#include <ros/common.h>
#include <ros/forwards.h>
#include <ros/init.h>
#include <ros/publisher.h>
#include <ros/rate.h>
#include <ros/service_client.h>
#include <ros/service_client_options.h>
#include <ros/service_server.h>
#include <ros/spinner.h>
#include <ros/steady_timer.h>
#include <ros/steady_timer_options.h>
#include <ros/subscribe_options.h>
#include <ros/subscriber.h>
#include <ros/timer.h>
#include <ros/timer_options.h>
#include <ros/wall_timer.h>
#include <ros/wall_timer_options.h>
#include <xmlrpcpp/XmlRpcValue.h>

namespace ros
{

class NodeHandleBackingCollection;

class NodeHandle
{
public:
  /// A handle in namespace `ns` (relative to the node's namespace; "~" the node's private
  /// namespace), with remappings of its own.
  NodeHandle(const std::string& ns = std::string(), const M_string& remappings = M_string());
  NodeHandle(const NodeHandle& rhs);
  /// A handle in `parent`'s namespace + "/" + `ns`.
  NodeHandle(const NodeHandle& parent, const std::string& ns);
  NodeHandle(const NodeHandle& parent, const std::string& ns, const M_string& remappings);
  ~NodeHandle();

  NodeHandle& operator=(const NodeHandle& rhs);

  /// The queue this handle's subscriptions, timers and connect callbacks go to.
  void setCallbackQueue(CallbackQueueInterface* queue);
  CallbackQueueInterface* getCallbackQueue() const;

  const std::string& getNamespace() const { return namespace_; }
  const std::string& getUnresolvedNamespace() const { return unresolved_namespace_; }

  /// `name` in this handle's namespace, remapped (with `remap`).  Throws InvalidNameException.
  std::string resolveName(const std::string& name, bool remap = true) const;

  // -- advertise ---------------------------------------------------------------------------

  template <class M>
  Publisher advertise(const std::string& topic, uint32_t queue_size, bool latch = false)
  {
    AdvertiseOptions ops;
    ops.template init<M>(topic, queue_size);
    ops.latch = latch;
    return advertise(ops);
  }

  template <class M>
  Publisher advertise(const std::string& topic, uint32_t queue_size, const SubscriberStatusCallback& connect_cb,
                      const SubscriberStatusCallback& disconnect_cb = SubscriberStatusCallback(),
                      const VoidConstPtr& tracked_object = VoidConstPtr(), bool latch = false)
  {
    AdvertiseOptions ops;
    ops.template init<M>(topic, queue_size, connect_cb, disconnect_cb);
    ops.tracked_object = tracked_object;
    ops.latch = latch;
    return advertise(ops);
  }

  Publisher advertise(AdvertiseOptions& ops);

  // -- subscribe ---------------------------------------------------------------------------

  template <class M, class T>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size, void (T::*fp)(M), T* obj,
                       const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template initByFullCallbackType<M>(topic, queue_size, boost::bind(fp, obj, boost::placeholders::_1));
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M, class T>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size, void (T::*fp)(M) const, T* obj,
                       const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template initByFullCallbackType<M>(topic, queue_size, boost::bind(fp, obj, boost::placeholders::_1));
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M, class T>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size,
                       void (T::*fp)(const boost::shared_ptr<M const>&), T* obj,
                       const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template init<M>(topic, queue_size, boost::bind(fp, obj, boost::placeholders::_1));
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M, class T>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size,
                       void (T::*fp)(const boost::shared_ptr<M const>&) const, T* obj,
                       const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template init<M>(topic, queue_size, boost::bind(fp, obj, boost::placeholders::_1));
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M, class T>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size, void (T::*fp)(M),
                       const boost::shared_ptr<T>& obj, const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template initByFullCallbackType<M>(topic, queue_size, boost::bind(fp, obj.get(), boost::placeholders::_1));
    ops.tracked_object = obj;
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M, class T>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size, void (T::*fp)(M) const,
                       const boost::shared_ptr<T>& obj, const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template initByFullCallbackType<M>(topic, queue_size, boost::bind(fp, obj.get(), boost::placeholders::_1));
    ops.tracked_object = obj;
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M, class T>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size,
                       void (T::*fp)(const boost::shared_ptr<M const>&), const boost::shared_ptr<T>& obj,
                       const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template init<M>(topic, queue_size, boost::bind(fp, obj.get(), boost::placeholders::_1));
    ops.tracked_object = obj;
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M, class T>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size,
                       void (T::*fp)(const boost::shared_ptr<M const>&) const, const boost::shared_ptr<T>& obj,
                       const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template init<M>(topic, queue_size, boost::bind(fp, obj.get(), boost::placeholders::_1));
    ops.tracked_object = obj;
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size, void (*fp)(M),
                       const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template initByFullCallbackType<M>(topic, queue_size, fp);
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size, void (*fp)(const boost::shared_ptr<M const>&),
                       const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template init<M>(topic, queue_size, fp);
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size,
                       const boost::function<void(const boost::shared_ptr<M const>&)>& callback,
                       const VoidConstPtr& tracked_object = VoidConstPtr(),
                       const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template init<M>(topic, queue_size, callback);
    ops.tracked_object = tracked_object;
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  template <class M, class C>
  Subscriber subscribe(const std::string& topic, uint32_t queue_size, const boost::function<void(C)>& callback,
                       const VoidConstPtr& tracked_object = VoidConstPtr(),
                       const TransportHints& transport_hints = TransportHints())
  {
    SubscribeOptions ops;
    ops.template initByFullCallbackType<C>(topic, queue_size, callback);
    ops.tracked_object = tracked_object;
    ops.transport_hints = transport_hints;
    return subscribe(ops);
  }

  Subscriber subscribe(SubscribeOptions& ops);

  // -- advertiseService --------------------------------------------------------------------

  template <class T, class MReq, class MRes>
  ServiceServer advertiseService(const std::string& service, bool (T::*srv_func)(MReq&, MRes&), T* obj)
  {
    AdvertiseServiceOptions ops;
    ops.template init<MReq, MRes>(service, boost::bind(srv_func, obj, boost::placeholders::_1, boost::placeholders::_2));
    return advertiseService(ops);
  }

  template <class T, class MReq, class MRes>
  ServiceServer advertiseService(const std::string& service, bool (T::*srv_func)(ServiceEvent<MReq, MRes>&), T* obj)
  {
    AdvertiseServiceOptions ops;
    ops.template initBySpecType<ServiceEvent<MReq, MRes> >(service, boost::bind(srv_func, obj, boost::placeholders::_1));
    return advertiseService(ops);
  }

  template <class T, class MReq, class MRes>
  ServiceServer advertiseService(const std::string& service, bool (T::*srv_func)(MReq&, MRes&),
                                 const boost::shared_ptr<T>& obj)
  {
    AdvertiseServiceOptions ops;
    ops.template init<MReq, MRes>(service,
                                  boost::bind(srv_func, obj.get(), boost::placeholders::_1, boost::placeholders::_2));
    ops.tracked_object = obj;
    return advertiseService(ops);
  }

  template <class T, class MReq, class MRes>
  ServiceServer advertiseService(const std::string& service, bool (T::*srv_func)(ServiceEvent<MReq, MRes>&),
                                 const boost::shared_ptr<T>& obj)
  {
    AdvertiseServiceOptions ops;
    ops.template initBySpecType<ServiceEvent<MReq, MRes> >(service,
                                                           boost::bind(srv_func, obj.get(), boost::placeholders::_1));
    ops.tracked_object = obj;
    return advertiseService(ops);
  }

  template <class MReq, class MRes>
  ServiceServer advertiseService(const std::string& service, bool (*srv_func)(MReq&, MRes&))
  {
    AdvertiseServiceOptions ops;
    ops.template init<MReq, MRes>(service, srv_func);
    return advertiseService(ops);
  }

  template <class MReq, class MRes>
  ServiceServer advertiseService(const std::string& service, bool (*srv_func)(ServiceEvent<MReq, MRes>&))
  {
    AdvertiseServiceOptions ops;
    ops.template initBySpecType<ServiceEvent<MReq, MRes> >(service, srv_func);
    return advertiseService(ops);
  }

  template <class MReq, class MRes>
  ServiceServer advertiseService(const std::string& service, const boost::function<bool(MReq&, MRes&)>& callback,
                                 const VoidConstPtr& tracked_object = VoidConstPtr())
  {
    AdvertiseServiceOptions ops;
    ops.template init<MReq, MRes>(service, callback);
    ops.tracked_object = tracked_object;
    return advertiseService(ops);
  }

  template <class S>
  ServiceServer advertiseService(const std::string& service, const boost::function<bool(S&)>& callback,
                                 const VoidConstPtr& tracked_object = VoidConstPtr())
  {
    AdvertiseServiceOptions ops;
    ops.template initBySpecType<S>(service, callback);
    ops.tracked_object = tracked_object;
    return advertiseService(ops);
  }

  ServiceServer advertiseService(AdvertiseServiceOptions& ops);

  // -- serviceClient -----------------------------------------------------------------------

  template <class MReq, class MRes>
  ServiceClient serviceClient(const std::string& service_name, bool persistent = false,
                              const M_string& header_values = M_string())
  {
    ServiceClientOptions ops;
    ops.template init<MReq, MRes>(service_name, persistent, header_values);
    return serviceClient(ops);
  }

  template <class Service>
  ServiceClient serviceClient(const std::string& service_name, bool persistent = false,
                              const M_string& header_values = M_string())
  {
    ServiceClientOptions ops;
    ops.template init<Service>(service_name, persistent, header_values);
    return serviceClient(ops);
  }

  ServiceClient serviceClient(ServiceClientOptions& ops);

  // -- timers ------------------------------------------------------------------------------

  template <class Handler, class Obj>
  Timer createTimer(Rate r, Handler h, Obj o, bool oneshot = false, bool autostart = true) const
  {
    return createTimer(r.expectedCycleTime(), h, o, oneshot, autostart);
  }

  template <class T>
  Timer createTimer(Duration period, void (T::*callback)(const TimerEvent&) const, T* obj, bool oneshot = false,
                    bool autostart = true) const
  {
    return createTimer(period, boost::bind(callback, obj, boost::placeholders::_1), oneshot, autostart);
  }

  template <class T>
  Timer createTimer(Duration period, void (T::*callback)(const TimerEvent&), T* obj, bool oneshot = false,
                    bool autostart = true) const
  {
    return createTimer(period, boost::bind(callback, obj, boost::placeholders::_1), oneshot, autostart);
  }

  template <class T>
  Timer createTimer(Duration period, void (T::*callback)(const TimerEvent&), const boost::shared_ptr<T>& obj,
                    bool oneshot = false, bool autostart = true) const
  {
    TimerOptions ops(period, boost::bind(callback, obj.get(), boost::placeholders::_1), 0);
    ops.tracked_object = obj;
    ops.oneshot = oneshot;
    ops.autostart = autostart;
    return createTimer(ops);
  }

  Timer createTimer(Duration period, const TimerCallback& callback, bool oneshot = false,
                    bool autostart = true) const;
  Timer createTimer(TimerOptions& ops) const;

  template <class T>
  WallTimer createWallTimer(WallDuration period, void (T::*callback)(const WallTimerEvent&), T* obj,
                            bool oneshot = false, bool autostart = true) const
  {
    return createWallTimer(period, boost::bind(callback, obj, boost::placeholders::_1), oneshot, autostart);
  }

  template <class T>
  WallTimer createWallTimer(WallDuration period, void (T::*callback)(const WallTimerEvent&),
                            const boost::shared_ptr<T>& obj, bool oneshot = false, bool autostart = true) const
  {
    WallTimerOptions ops(period, boost::bind(callback, obj.get(), boost::placeholders::_1), 0);
    ops.tracked_object = obj;
    ops.oneshot = oneshot;
    ops.autostart = autostart;
    return createWallTimer(ops);
  }

  WallTimer createWallTimer(WallDuration period, const WallTimerCallback& callback, bool oneshot = false,
                            bool autostart = true) const;
  WallTimer createWallTimer(WallTimerOptions& ops) const;

  template <class T>
  SteadyTimer createSteadyTimer(WallDuration period, void (T::*callback)(const SteadyTimerEvent&), T* obj,
                                bool oneshot = false, bool autostart = true) const
  {
    return createSteadyTimer(period, boost::bind(callback, obj, boost::placeholders::_1), oneshot, autostart);
  }

  template <class T>
  SteadyTimer createSteadyTimer(WallDuration period, void (T::*callback)(const SteadyTimerEvent&),
                                const boost::shared_ptr<T>& obj, bool oneshot = false, bool autostart = true) const
  {
    SteadyTimerOptions ops(period, boost::bind(callback, obj.get(), boost::placeholders::_1), 0);
    ops.tracked_object = obj;
    ops.oneshot = oneshot;
    ops.autostart = autostart;
    return createSteadyTimer(ops);
  }

  SteadyTimer createSteadyTimer(WallDuration period, const SteadyTimerCallback& callback, bool oneshot = false,
                                bool autostart = true) const;
  SteadyTimer createSteadyTimer(SteadyTimerOptions& ops) const;

  // -- parameters --------------------------------------------------------------------------

  void setParam(const std::string& key, const XmlRpc::XmlRpcValue& v) const;
  void setParam(const std::string& key, const std::string& s) const;
  void setParam(const std::string& key, const char* s) const;
  void setParam(const std::string& key, double d) const;
  void setParam(const std::string& key, int i) const;
  void setParam(const std::string& key, bool b) const;
  void setParam(const std::string& key, const std::vector<std::string>& vec) const;
  void setParam(const std::string& key, const std::vector<double>& vec) const;
  void setParam(const std::string& key, const std::vector<float>& vec) const;
  void setParam(const std::string& key, const std::vector<int>& vec) const;
  void setParam(const std::string& key, const std::vector<bool>& vec) const;
  void setParam(const std::string& key, const std::map<std::string, std::string>& map) const;
  void setParam(const std::string& key, const std::map<std::string, double>& map) const;
  void setParam(const std::string& key, const std::map<std::string, float>& map) const;
  void setParam(const std::string& key, const std::map<std::string, int>& map) const;
  void setParam(const std::string& key, const std::map<std::string, bool>& map) const;

  bool getParam(const std::string& key, std::string& s) const;
  bool getParam(const std::string& key, double& d) const;
  bool getParam(const std::string& key, float& f) const;
  bool getParam(const std::string& key, int& i) const;
  bool getParam(const std::string& key, bool& b) const;
  bool getParam(const std::string& key, XmlRpc::XmlRpcValue& v) const;
  bool getParam(const std::string& key, std::vector<std::string>& vec) const;
  bool getParam(const std::string& key, std::vector<double>& vec) const;
  bool getParam(const std::string& key, std::vector<float>& vec) const;
  bool getParam(const std::string& key, std::vector<int>& vec) const;
  bool getParam(const std::string& key, std::vector<bool>& vec) const;
  bool getParam(const std::string& key, std::map<std::string, std::string>& map) const;
  bool getParam(const std::string& key, std::map<std::string, double>& map) const;
  bool getParam(const std::string& key, std::map<std::string, float>& map) const;
  bool getParam(const std::string& key, std::map<std::string, int>& map) const;
  bool getParam(const std::string& key, std::map<std::string, bool>& map) const;

  bool getParamCached(const std::string& key, std::string& s) const;
  bool getParamCached(const std::string& key, double& d) const;
  bool getParamCached(const std::string& key, float& f) const;
  bool getParamCached(const std::string& key, int& i) const;
  bool getParamCached(const std::string& key, bool& b) const;
  bool getParamCached(const std::string& key, XmlRpc::XmlRpcValue& v) const;
  bool getParamCached(const std::string& key, std::vector<std::string>& vec) const;
  bool getParamCached(const std::string& key, std::vector<double>& vec) const;
  bool getParamCached(const std::string& key, std::vector<float>& vec) const;
  bool getParamCached(const std::string& key, std::vector<int>& vec) const;
  bool getParamCached(const std::string& key, std::vector<bool>& vec) const;
  bool getParamCached(const std::string& key, std::map<std::string, std::string>& map) const;
  bool getParamCached(const std::string& key, std::map<std::string, double>& map) const;
  bool getParamCached(const std::string& key, std::map<std::string, float>& map) const;
  bool getParamCached(const std::string& key, std::map<std::string, int>& map) const;
  bool getParamCached(const std::string& key, std::map<std::string, bool>& map) const;

  bool hasParam(const std::string& key) const;
  /// Searches up from this handle's namespace; the full key found in `result`.
  bool searchParam(const std::string& key, std::string& result) const;
  bool deleteParam(const std::string& key) const;
  bool getParamNames(std::vector<std::string>& keys) const;

  template <typename T>
  bool param(const std::string& param_name, T& param_val, const T& default_val) const
  {
    if (hasParam(param_name))
    {
      if (getParam(param_name, param_val))
        return true;
    }
    param_val = default_val;
    return false;
  }

  template <typename T>
  T param(const std::string& param_name, const T& default_val) const
  {
    T param_val;
    param(param_name, param_val, default_val);
    return param_val;
  }

  /// Ends everything made through this handle; ok() is false afterwards.
  void shutdown();
  /// ros::ok() and this handle not shut down.
  bool ok() const;

private:
  void construct(const std::string& ns, bool validate_name);
  void destruct();
  void initRemappings(const M_string& remappings);
  /// What a request about `name` sends the world: validated as resolveName validates, and
  /// this handle's own remappings applied (the world applies the node's).
  void worldName(const std::string& name, std::string& ns_out, std::string& name_out) const;

  std::string namespace_;
  std::string unresolved_namespace_;
  M_string remappings_;
  M_string unresolved_remappings_;

  CallbackQueueInterface* callback_queue_;
  NodeHandleBackingCollection* collection_;

  bool ok_;
};

}  // namespace ros

#endif  // ROSCPP_NODE_HANDLE_H
