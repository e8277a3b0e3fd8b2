// ddes roscpp: the container typedefs roscpp's API uses (M_string, V_string, ...).
#ifndef ROSCPP_DATATYPES_H
#define ROSCPP_DATATYPES_H

#include <list>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <boost/shared_ptr.hpp>

namespace ros
{

typedef std::vector<std::pair<std::string, std::string> > VP_string;
typedef std::vector<std::string> V_string;
typedef std::set<std::string> S_string;
typedef std::map<std::string, std::string> M_string;
typedef std::pair<std::string, std::string> StringPair;

typedef boost::shared_ptr<M_string> M_stringPtr;

}  // namespace ros

#endif  // ROSCPP_DATATYPES_H
