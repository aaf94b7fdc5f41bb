/*
 * frames.h — pictures of a session: one PNG at a time t (frame.png) and an
 * animation (frames) of the stored run, drawn by render/ (render.h).
 *
 * A frame never touches the session's live ts_data: the state at the frame's
 * sample index k is rebuilt in a scratch ts_data from the latest stored
 * snapshot with index <= k (db.h: one per stored batch), advanced to k with
 * the shared read-only model, then ts_geometry takes the snapshot render/
 * draws. So frames of past times and of a running session are exactly the
 * stored trajectory, and rendering never waits for a run. Rebuilding and
 * drawing are physics/GL work: they run on the worker pool; the HTTP thread
 * only suspends the connection and resumes it when the PNG is ready.
 *
 * OpenGL contexts (tsr_ctx) are kept in a small free list: a job takes one
 * (creating it on first use), draws, and gives it back — at most one per
 * worker thread ever exists.
 *
 * Animation: by default one APNG (render/apng.h: self-contained, lossless,
 * animated by every current browser, shown as its first frame by any PNG
 * reader; at most TSD_MAX_APNG_FRAMES frames); with format=multipart the frames
 * stream as multipart/x-mixed-replace; boundary=frame, one image/png part
 * per frame at t_i = from + i / fps (i = 0, 1, ... while t_i <= to), each part
 * with X-Frame-Time and X-Frame-Index headers. Browsers show it as a moving
 * image in an <img>; clients split it on the boundary. The first frame is
 * drawn before the response starts, so a session whose scenario has no
 * geometry (pointmass) gets a 422 problem instead of an empty stream.
 *
 * An APNG is one pool job of up to TSD_MAX_APNG_FRAMES frames, so it is
 * bounded twice: it is a long job (server.h: with the analyses, at most
 * threads - 1 at once; one more answers 429 with Retry-After, so long jobs
 * never take every worker from runs and steps), and it stops between frames when the daemon is
 * stopping, the session has been deleted, or the client has hung up
 * (libmicrohttpd does not watch a suspended connection, so the job polls
 * the socket itself).
 */
#ifndef TSD_FRAMES_H
#define TSD_FRAMES_H

#include "../render/render.h"
#include "server.h"
#include "session.h"

#define TSD_MAX_FRAMES 3000      /* frames per multipart animation request */
#define TSD_MAX_APNG_FRAMES 600  /* frames per APNG (held in memory until sent) */

TS_MUST_CHECK int tsd_renderers_init(tsd_server *srv);
void tsd_renderers_free(tsd_server *srv); /* after the pool has stopped */

/* Start drawing frames of session s for sample indexes k0, k0 + dk, ... (n
 * frames, n = 1 for frame.png) with view v; the request is suspended and
 * answered when the first frame is ready (image/png when single), or, with
 * apng_fps > 0, when all n frames are drawn (one image/apng shown at that
 * rate), else as the multipart stream. */
enum MHD_Result tsd_frames_reply(tsd_request *r, tsd_session *s, const tsr_view *v, double k0,
                                 double dk, long n, int single, double apng_fps);

#endif
