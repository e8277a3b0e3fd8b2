// ddes roscpp, internal: parameters in a namespace (what NodeHandle and ros::param share).
#ifndef DDES_ROSCPP_PARAM_IMPL_H
#define DDES_ROSCPP_PARAM_IMPL_H

#include <map>
#include <string>
#include <vector>

#include <xmlrpcpp/XmlRpcValue.h>

#define DDES_COMMA ,

namespace ros
{
namespace ddes
{

class Writer;
class Reader;

/// A value in the protocol's tagged form, and back.
void writeValue(Writer& w, const XmlRpc::XmlRpcValue& v);
XmlRpc::XmlRpcValue readValue(Reader& r, int depth = 0);

XmlRpc::XmlRpcValue toXmlRpc(const XmlRpc::XmlRpcValue& v);
XmlRpc::XmlRpcValue toXmlRpc(const std::string& v);
XmlRpc::XmlRpcValue toXmlRpc(const char* v);
XmlRpc::XmlRpcValue toXmlRpc(double v);
XmlRpc::XmlRpcValue toXmlRpc(int v);
XmlRpc::XmlRpcValue toXmlRpc(bool v);
XmlRpc::XmlRpcValue toXmlRpc(const std::vector<std::string>& v);
XmlRpc::XmlRpcValue toXmlRpc(const std::vector<double>& v);
XmlRpc::XmlRpcValue toXmlRpc(const std::vector<float>& v);
XmlRpc::XmlRpcValue toXmlRpc(const std::vector<int>& v);
XmlRpc::XmlRpcValue toXmlRpc(const std::vector<bool>& v);
XmlRpc::XmlRpcValue toXmlRpc(const std::map<std::string, std::string>& v);
XmlRpc::XmlRpcValue toXmlRpc(const std::map<std::string, double>& v);
XmlRpc::XmlRpcValue toXmlRpc(const std::map<std::string, float>& v);
XmlRpc::XmlRpcValue toXmlRpc(const std::map<std::string, int>& v);
XmlRpc::XmlRpcValue toXmlRpc(const std::map<std::string, bool>& v);

/// `key` read in namespace `ns` ("~key": the node's private namespace), remapped by the world.
void paramSet(const std::string& ns, const std::string& key, const XmlRpc::XmlRpcValue& v);
bool paramGet(const std::string& ns, const std::string& key, XmlRpc::XmlRpcValue& v, bool cached);
bool paramHas(const std::string& ns, const std::string& key);
bool paramDelete(const std::string& ns, const std::string& key);
bool paramSearch(const std::string& ns, const std::string& key, std::string& result);
bool paramNames(std::vector<std::string>& keys);

/// roscpp's typed reads (its conversions: an int read as a double, a double rounded to an
/// int, vectors element by element, ...).
bool paramGetAs(const std::string& ns, const std::string& key, XmlRpc::XmlRpcValue& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::string& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, double& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, float& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, int& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, bool& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::vector<std::string>& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::vector<double>& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::vector<float>& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::vector<int>& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::vector<bool>& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::map<std::string, std::string>& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::map<std::string, double>& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::map<std::string, float>& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::map<std::string, int>& v, bool cached);
bool paramGetAs(const std::string& ns, const std::string& key, std::map<std::string, bool>& v, bool cached);

}  // namespace ddes
}  // namespace ros

#endif  // DDES_ROSCPP_PARAM_IMPL_H
