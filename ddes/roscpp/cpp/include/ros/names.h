// ddes roscpp: ros::names, graph resource names (roscpp's rules).  validate, clean, append and
// parentNamespace are computed here; resolving with remapping asks the world (RESOLVE), which
// holds the node's remappings (its command line's and the launch file's).
#ifndef ROSCPP_NAMES_H
#define ROSCPP_NAMES_H

#include <string>

#include <ros/common.h>
#include <ros/forwards.h>

namespace ros
{
namespace names
{

/// The remappings of this process's command line ("from:=to"), resolved.
const M_string& getRemappings();
/// The same, as written.
const M_string& getUnresolvedRemappings();

/// `name` in the node's namespace ("~" the node's private namespace), remapped if asked.
std::string resolve(const std::string& name, bool remap = true);
/// `name` in namespace `ns`, remapped if asked.  Throws InvalidNameException.
std::string resolve(const std::string& ns, const std::string& name, bool remap = true);
/// No double or trailing slashes.
std::string clean(const std::string& name);
/// left + "/" + right, cleaned.
std::string append(const std::string& left, const std::string& right);
/// The name a remapping maps `name` to, or `name`.
std::string remap(const std::string& name);
/// Whether `name` is a valid graph resource name; if not, `error` says why.
bool validate(const std::string& name, std::string& error);
/// The namespace above `name` ("/a/b" -> "/a", "/a" -> "/").
std::string parentNamespace(const std::string& name);

}  // namespace names
}  // namespace ros

#endif  // ROSCPP_NAMES_H
