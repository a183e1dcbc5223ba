// softface serve (serve): the planner behind HTTP and WebSocket routes, the
// page's files from the web folder, a re-plan per WebSocket message.

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <softface/core/error.h>
#include <softface/serve/serve.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#ifndef SOFTFACE_WEB_DIRECTORY
#  define SOFTFACE_WEB_DIRECTORY "web"
#endif

namespace softface
{
  namespace Serve
  {
    namespace
    {
      std::string
      json_string(const std::string &text)
      {
        std::string quoted = "\"";
        for (const char c : text)
          if (c == '"' || c == '\\')
            quoted += std::string("\\") + c;
          else if (static_cast<unsigned char>(c) < 0x20)
            quoted += ' ';
          else
            quoted += c;
        return quoted + '"';
      }

      template <typename T>
      void
      append(std::string &bytes, const T value)
      {
        char raw[sizeof(T)];
        std::memcpy(raw, &value, sizeof(T));
        bytes.append(raw, sizeof(T));
      }

      std::string
      surface_bytes(const SurfaceMapping::Surface &surface)
      {
        std::string bytes;
        bytes.reserve(8 + 12 * surface.points.size() +
                      12 * surface.triangles.size());
        append<std::uint32_t>(bytes, surface.points.size());
        append<std::uint32_t>(bytes, surface.triangles.size());
        for (const auto &p : surface.points)
          for (unsigned int d = 0; d < 3; ++d)
            append<float>(bytes, p[d]);
        for (const auto &t : surface.triangles)
          for (unsigned int k = 0; k < 3; ++k)
            append<std::uint32_t>(bytes, t[k]);
        return bytes;
      }

      RequestHandler::Reply
      file_reply(const std::string &path, const std::string &content_type)
      {
        std::ifstream in(path, std::ios::binary);
        if (!in)
          return {404,
                  "text/plain",
                  "not found: " + path +
                    " (the page's files come from the web folder; ./run.sh "
                    "installs three.js into web/node_modules)\n"};
        std::ostringstream body;
        body << in.rdbuf();
        return {200, content_type, body.str()};
      }
    } // namespace

    PlannerHandler::PlannerHandler(const InteractivePlanner &planner,
                                   const std::string        &web_directory)
        : planner(planner)
        , web(web_directory)
    {}

    RequestHandler::Reply
    PlannerHandler::get(const std::string &target)
    {
      const std::string path = target.substr(0, target.find('?'));
      if (path == "/" || path == "/index.html")
        return file_reply(web + "/index.html", "text/html; charset=utf-8");
      if (path == "/app.js")
        return file_reply(web + "/app.js", "text/javascript");
      if (path == "/three/three.module.js")
        return file_reply(web + "/node_modules/three/build/three.module.js",
                          "text/javascript");
      const std::string addons = "/three/addons/";
      if (path.rfind(addons, 0) == 0)
        {
          const std::string rest = path.substr(addons.size());
          // Only files below the add-ons folder.
          if (rest.find("..") != std::string::npos || rest.empty())
            return {403, "text/plain", "forbidden\n"};
          return file_reply(web + "/node_modules/three/examples/jsm/" + rest,
                            "text/javascript");
        }
      if (path == "/scene.json")
        {
          std::ostringstream json;
          json << std::setprecision(9)
               << "{\"surface\":" << json_string(planner.surface_kind())
               << ",\"points\":" << planner.surface().points.size()
               << ",\"triangles\":" << planner.surface().triangles.size()
               << ",\"post_operative\":"
               << (planner.post_operative().points.empty() ? "false" : "true")
               << ",\"limits\":{\"translation\":"
               << planner.parameters().translation_limit
               << ",\"rotation\":" << planner.parameters().rotation_limit
               << "},\"models\":[";
          const auto models = planner.model_names();
          for (unsigned int m = 0; m < models.size(); ++m)
            json << (m > 0 ? "," : "") << json_string(models[m]);
          json << "],\"segments\":[";
          const auto &segments = planner.moved_segments();
          for (unsigned int s = 0; s < segments.size(); ++s)
            json << (s > 0 ? "," : "")
                 << "{\"name\":" << json_string(segments[s].name)
                 << ",\"centre\":[" << segments[s].centre[0] << ','
                 << segments[s].centre[1] << ',' << segments[s].centre[2]
                 << "]}";
          json << "]}";
          return {200, "application/json", json.str()};
        }
      if (path == "/surface.bin")
        return {200,
                "application/octet-stream",
                surface_bytes(planner.surface())};
      if (path == "/moving.bin")
        {
          std::string bytes;
          append<std::uint32_t>(bytes, planner.moving_points().size());
          for (const unsigned int i : planner.moving_points())
            append<std::uint32_t>(bytes, i);
          return {200, "application/octet-stream", bytes};
        }
      if (path == "/rest_distance.bin")
        {
          const auto &d = planner.rest_distances();
          if (d.empty())
            return {404,
                    "text/plain",
                    "the scene has no post-operative skin\n"};
          return {200,
                  "application/octet-stream",
                  std::string(reinterpret_cast<const char *>(d.data()),
                              4 * d.size())};
        }
      if (path == "/postop.bin")
        {
          if (planner.post_operative().points.empty())
            return {404,
                    "text/plain",
                    "the scene has no post-operative skin\n"};
          return {200,
                  "application/octet-stream",
                  surface_bytes(planner.post_operative())};
        }
      return {404, "text/plain", "not found: " + path + "\n"};
    }

    RequestHandler::Message
    PlannerHandler::message(const std::string &text)
    {
      namespace pt = boost::property_tree;
      long id      = -1;
      try
        {
          // Boost's JSON parser recurses once per nesting level: a deep
          // request is refused before it can exhaust the stack.
          int depth = 0;
          for (const char c : text)
            if ((c == '[' || c == '{') && ++depth > 8)
              throw Error("the request nests deeper than a plan does.");
            else if (c == ']' || c == '}')
              --depth;
          pt::ptree          request;
          std::istringstream in(text);
          try
            {
              pt::read_json(in, request);
            }
          catch (const pt::json_parser_error &e)
            {
              throw Error("the request is not JSON (" + e.message() + ").");
            }
          id = request.get<long>("id", -1);
          if (id < -1 || id > 4294967295L)
            {
              id = -1;
              throw Error("'id' must be a whole number from 0 to 2^32 - 1.");
            }
          const std::string model =
            request.get<std::string>("model", planner.model_names()[0]);

          const auto &segments = planner.moved_segments();
          std::vector<InteractivePlanner::Motion> motions(
            segments.size(), InteractivePlanner::Motion{});
          if (const auto given = request.get_child_optional("motions"))
            for (const auto &[name, values] : *given)
              {
                unsigned int s = 0;
                while (s < segments.size() && segments[s].name != name)
                  ++s;
                if (s == segments.size())
                  throw Error("unknown segment '" + name +
                              "' (the moved segments are in /scene.json).");
                unsigned int k = 0;
                for (const auto &[key, value] : values)
                  {
                    if (k == 6)
                      throw Error("segment '" + name +
                                  "': a motion is six numbers [tx, ty, tz, "
                                  "rx, ry, rz].");
                    const std::string number = value.get_value<std::string>();
                    // Decimal numbers only (std::stod also reads hex, inf).
                    if (number.find_first_not_of("0123456789+-.eE") !=
                        std::string::npos)
                      throw Error("segment '" + name + "': '" + number +
                                  "' is not a number.");
                    std::size_t used = 0;
                    double      v    = 0.;
                    try
                      {
                        v = std::stod(number, &used);
                      }
                    catch (const std::exception &)
                      {
                        used = 0;
                      }
                    if (used == 0 || used != number.size())
                      throw Error("segment '" + name + "': '" + number +
                                  "' is not a number.");
                    motions[s][k++] = v;
                  }
                if (k != 6)
                  throw Error("segment '" + name +
                              "': a motion is six numbers [tx, ty, tz, rx, "
                              "ry, rz].");
              }

          const auto result =
            planner.replan(model,
                           motions,
                           request.get<bool>("distance", false));
          std::string bytes;
          bytes.reserve(24 + 4 * result.displacement.size() +
                        4 * result.distance.size());
          append<std::uint32_t>(bytes, id < 0 ? 0 : id);
          append<float>(bytes, result.combination_ms);
          append<float>(bytes, result.mapping_ms);
          append<float>(bytes, result.distance_ms);
          append<std::uint32_t>(bytes, result.displacement.size() / 3);
          append<std::uint32_t>(bytes, result.distance.empty() ? 0 : 1);
          bytes.append(reinterpret_cast<const char *>(
                         result.displacement.data()),
                       4 * result.displacement.size());
          bytes.append(reinterpret_cast<const char *>(result.distance.data()),
                       4 * result.distance.size());
          return {true, bytes};
        }
      catch (const std::exception &e)
        {
          return {false,
                  "{\"id\":" + std::to_string(id) +
                    ",\"error\":" + json_string(e.what()) + "}"};
        }
    }

    int
    serve(const std::string &scene_file, std::ostream &out)
    {
      out << "softface serve: " << scene_file << std::endl;
      InteractivePlanner planner(scene_file, out);
      const auto        &parameters = planner.parameters();
      const std::string  web        = parameters.web_directory.empty() ?
                                        std::string(SOFTFACE_WEB_DIRECTORY) :
                                        parameters.web_directory;
      if (!std::filesystem::exists(web + "/node_modules/three/build/"
                                         "three.module.js"))
        out << "softface serve: warning: three.js is not installed in " << web
            << "/node_modules (run: cd " << web
            << " && npm ci); the page will not draw." << std::endl;
      out << "  " << planner.surface_kind() << ": "
          << planner.surface().points.size() << " points, "
          << planner.surface().triangles.size() << " triangles" << std::endl;
      PlannerHandler handler(planner, web);
      run_server(parameters.address, parameters.port, handler, out);
      return 0;
    }
  } // namespace Serve
} // namespace softface
