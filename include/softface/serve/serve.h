#ifndef softface_serve_serve_h
#define softface_serve_serve_h

#include <softface/serve/http_server.h>
#include <softface/serve/interactive_planner.h>

#include <ostream>
#include <string>

namespace softface
{
  namespace Serve
  {
    /**
     * What `softface serve` answers (RequestHandler), over an
     * InteractivePlanner:
     *  - GET / (the page: web/index.html), /app.js, /three/... (three.js
     *    from the web folder's node_modules);
     *  - GET /scene.json: the moved segments with their centres, the
     *    models, the limits, the surface's kind and size;
     *  - GET /surface.bin and /postop.bin: a surface as uint32 points,
     *    uint32 triangles, float32 x,y,z per point, uint32 indices per
     *    triangle (little-endian; /postop.bin is 404 without one);
     *  - GET /moving.bin: uint32 count, then the uint32 index of every
     *    surface point a plan can move (a re-plan sends only theirs);
     *  - GET /rest_distance.bin: float32 signed distance (mm) of every
     *    surface point at rest to the post-operative skin (404 without);
     *  - a WebSocket text message {"id": k, "model": "...", "motions":
     *    {"<segment>": [tx, ty, tz, rx, ry, rz], ...}, "distance": true}
     *    (mm, degrees about x, y, z through the segment's centre; a segment
     *    left out stays; "distance" optional) gets a binary answer: uint32
     *    k, float32 combination ms, float32 mapping ms, float32 distance ms,
     *    uint32 count, uint32 flags (1: distances follow), float32
     *    displacement x,y,z of each moving point (in /moving.bin's order),
     *    then, with the flag, float32 signed distance of each moving point
     *    to the post-operative skin; a bad one
     *    gets the text {"id": k, "error": "..."} and the server serves on.
     */
    class PlannerHandler : public RequestHandler
    {
    public:
      PlannerHandler(const InteractivePlanner &planner,
                     const std::string        &web_directory);

      Reply
      get(const std::string &target) override;
      Message
      message(const std::string &text) override;

    private:
      const InteractivePlanner &planner;
      std::string               web;
    };

    /// `softface serve SCENE.prm`: returns the exit code.
    int
    serve(const std::string &scene_file, std::ostream &out);
  } // namespace Serve
} // namespace softface

#endif
