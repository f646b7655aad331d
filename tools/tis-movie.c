/* tis-movie - a movie of a run: the frames of a mesh stream (tis-active
 * --every) or of a .pvd collection (tis-vtk) gathered by libmesh/draw/movie.c,
 * drawn by raster.c and piped to ffmpeg as raw RGB video. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "cli_spawn.h"
#include "measure.h"
#include "movie.h"
#include "raster.h"

static const char usage[] =
	"-o FILE [--format mp4|gif|ppm] [--fps N] [--width PX] [--window W] [--scale S]\n"
	"       [--junction A B | --no-mark] [--p0 X] [--ffmpeg PROG] [FRAMES | RUN.pvd]";
static const char help[] =
	"Make a movie of a run: every mesh of a tismesh stream (the frames of\n"
	"tis-active --every or tis-anneal --every) or every dataset of a .pvd\n"
	"collection (tis-vtk -o) is one frame: cells by side count, junctions by\n"
	"line tension 2 (P1 - p0) + 2 (P2 - p0) + dg on a blue-white-red map,\n"
	"the active junctions (nonzero dg, when at most 8) marked in green, the\n"
	"time in the upper left corner.  Encoded by ffmpeg into MP4 (H.264) or GIF.\n"
	"\n"
	"  -o, --output FILE  the movie; its suffix .mp4 or .gif is the format;\n"
	"                     - with --format ppm: the frames as PPM on stdout\n"
	"  --format F         mp4, gif or ppm (no ffmpeg needed), whatever the suffix\n"
	"  --fps N            frames per second (default 10)\n"
	"  --width PX         width of the drawn box in pixels (default 480)\n"
	"  --window W         draw a part W wide (in sqrt(A0): a cell is about 1 wide)\n"
	"                     about the marked junction of the first frame, not the\n"
	"                     whole box (W 6: the area of some 30 cells)\n"
	"  --scale S          tension at full colour (default: the largest |tension|\n"
	"                     of any frame)\n"
	"  --junction A B     mark the junction joining vertices A and B instead\n"
	"  --no-mark          mark no junction\n"
	"  --p0 X             shape index for the tension (default: the frame's)\n"
	"  --ffmpeg PROG      the encoder to run (default ffmpeg, found on PATH)\n"
	"  -h, --help         this help\n"
	"  --version          print the version\n";

enum { FMT_MP4, FMT_GIF, FMT_PPM };

struct opts {
	const char *out, *ffmpeg, *input;
	int format, fps, width, nomark;
	cli_model_opts mo;   /* --p0 */
	double window;    /* 0: the whole box */
	long ja, jb;      /* --junction, ja < 0: none */
	double scale;
};

static struct opts parse(int argc, char **argv)
{
	enum { O_FORMAT = 256, O_FPS, O_WIDTH, O_WINDOW, O_SCALE, O_JUNCTION, O_NOMARK, O_P0, O_FFMPEG, O_VERSION };
	static const struct option lo[] = {
		{ "output", required_argument, NULL, 'o' },
		{ "format", required_argument, NULL, O_FORMAT },
		{ "fps", required_argument, NULL, O_FPS },
		{ "width", required_argument, NULL, O_WIDTH },
		{ "window", required_argument, NULL, O_WINDOW },
		{ "scale", required_argument, NULL, O_SCALE },
		{ "junction", required_argument, NULL, O_JUNCTION },
		{ "no-mark", no_argument, NULL, O_NOMARK },
		{ "p0", required_argument, NULL, O_P0 },
		{ "ffmpeg", required_argument, NULL, O_FFMPEG },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, O_VERSION },
		{ 0 }
	};
	struct opts o = { .format = -1, .fps = 10, .width = 480, .ja = -1, .ffmpeg = "ffmpeg" };
	int c;
	while ((c = getopt_long(argc, argv, ":ho:", lo, NULL)) != -1) {
		switch (c) {
		case 'o': o.out = optarg; break;
		case O_FORMAT:
			o.format = !strcmp(optarg, "mp4") ? FMT_MP4 : !strcmp(optarg, "gif") ? FMT_GIF
				 : !strcmp(optarg, "ppm") ? FMT_PPM : -2;
			if (o.format == -2)
				cli_usage_error("--format: mp4, gif or ppm, not '%s'", optarg);
			break;
		case O_FPS: o.fps = (int)cli_long("--fps", optarg, 1, 240); break;
		case O_WIDTH: o.width = (int)cli_long("--width", optarg, 16, 8192); break;
		case O_WINDOW: o.window = cli_double_range("--window", optarg, 1e-3, 1e6); break;
		case O_SCALE: o.scale = cli_double_range("--scale", optarg, 1e-12, 1e12); break;
		case O_JUNCTION: cli_vertex_pair("--junction", argc, argv, &o.ja, &o.jb); break;
		case O_NOMARK: o.nomark = 1; break;
		case O_P0: cli_model_option(&o.mo, "p0", optarg); break;
		case O_FFMPEG: o.ffmpeg = optarg; break;
		case 'h': cli_help(help);
		case O_VERSION: cli_version();
		default: cli_bad_option(argv, c);
		}
	}
	if (o.out == NULL)
		cli_usage_error("-o FILE is needed (name.mp4, name.gif, or - with --format ppm)");
	if (o.nomark && o.ja >= 0)
		cli_usage_error("--junction and --no-mark: choose one");
	if (o.nomark && o.window > 0)
		cli_usage_error("--window is about the marked junction: not with --no-mark");
	const char *dot = strrchr(o.out, '.');
	if (o.format < 0)
		o.format = dot && !strcmp(dot, ".mp4") ? FMT_MP4 : dot && !strcmp(dot, ".gif") ? FMT_GIF : -1;
	if (o.format < 0)
		cli_usage_error("%s: give a name ending in .mp4 or .gif, or --format", o.out);
	if (!strcmp(o.out, "-") && o.format != FMT_PPM)
		cli_usage_error("-o -: only --format ppm goes to stdout (MP4 and GIF need a file)");
	if (argc - optind > 1)
		cli_usage_error("at most one input");
	o.input = optind < argc ? argv[optind] : NULL;
	return o;
}

/* The junctions frame i marks into mark: --junction's, else the active
 * ones (raster_active); how many. */
static int marks(const struct opts *o, const mesh *m, int i, int *mark)
{
	if (o->nomark)
		return 0;
	if (o->ja < 0)
		return raster_active(m, mark);
	mark[0] = mesh_junction_find(m, (int)o->ja, (int)o->jb);
	if (mark[0] < 0)
		cli_die(EXIT_INPUT, "frame %d: %ld-%ld is not a junction", i, o->ja, o->jb);
	return 1;
}

/* ffmpeg reading raw RGB frames from a pipe: its pid, *fd the pipe. */
static pid_t encoder(const struct opts *o, int w, int h, int *fd, int *errfd)
{
	char size[32], fps[16];
	snprintf(size, sizeof size, "%dx%d", w, h);
	snprintf(fps, sizeof fps, "%d", o->fps);
	const char *mp4[] = { "-c:v", "libx264", "-pix_fmt", "yuv420p", "-preset", "veryfast",
			      "-crf", "20", "-movflags", "+faststart", NULL };
	const char *gif[] = { "-vf", "split[a][b];[a]palettegen=stats_mode=full[p];[b][p]paletteuse",
			      "-loop", "0", NULL };
	const char *argv[32] = { o->ffmpeg, "-hide_banner", "-nostats", "-loglevel", "error", "-y",
				 "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", size, "-framerate", fps,
				 "-i", "-" };
	int k = 16;
	for (const char **a = o->format == FMT_GIF ? gif : mp4; *a; a++)
		argv[k++] = *a;
	argv[k++] = o->out;
	argv[k] = NULL;
	return cli_spawn(argv, "install Debian's ffmpeg, or give --ffmpeg PROG", fd, errfd);
}

static void put(int fd, const unsigned char *p, size_t n)
{
	while (n > 0) {
		ssize_t k = write(fd, p, n);
		if (k < 0 && errno == EINTR)
			continue;
		if (k <= 0)
			return;   /* the encoder went away: cli_spawn_wait says why */
		p += k;
		n -= (size_t)k;
	}
}

int main(int argc, char **argv)
{
	cli_init("tis-movie", usage, argc, argv);
	struct opts o = parse(argc, argv);
	movie_frames fr = { 0 };
	mesh_error err;
	const char *dot = o.input ? strrchr(o.input, '.') : NULL;
	FILE *f = cli_open(o.input);
	if (dot && !strcmp(dot, ".pvd")) {
		if (movie_frames_read_pvd(&fr, f, o.input, &err) != MESH_OK)
			cli_die(EXIT_INPUT, "%s", err.msg);
	} else {
		long line = 0;
		mesh *m;
		double t;
		while (cli_read_mesh(f, o.input, &line, &m))
			if (movie_frames_add(&fr, m, mesh_time(m, &t) ? t : NAN, &err) != MESH_OK)
				cli_die(EXIT_INPUT, "%s", err.msg);
	}
	if (f != stdin)
		fclose(f);
	if (fr.n == 0)
		cli_no_mesh(o.input);
	double scale = o.scale;
	if (scale == 0 && movie_frames_scale(&fr, o.mo.has_p0 ? &o.mo.p0 : NULL, &scale) != MESH_OK)
		cli_die(EXIT_INPUT, "out of memory");
	raster_opts ro = { .width = o.width, .scale = scale };
	int *mark = malloc(((size_t)fr.m[0]->nj + 1) * sizeof *mark);
	if (mark == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	if (o.window > 0) {
		if (marks(&o, fr.m[0], 0, mark) == 0)
			cli_die(EXIT_INPUT, "--window: the first frame has no marked junction (give --junction A B)");
		raster_view_junction(fr.m[0], mark[0], o.window, ro.view);
	}
	int w, h;
	raster_size(fr.m[0]->lx, fr.m[0]->ly, &ro, &w, &h);
	raster *img = raster_alloc(w, h);
	if (img == NULL)
		cli_die(EXIT_INPUT, "out of memory");
	int fd = 1, errfd = -1;
	pid_t pid = o.format == FMT_PPM ? 0 : encoder(&o, w, h, &fd, &errfd);
	for (int i = 0; i < fr.n; i++) {
		mesh *m = fr.m[i];
		model p = cli_model(m, &o.mo);
		free(mark);
		mark = malloc(((size_t)m->nj + 1) * sizeof *mark);
		if (mark == NULL)
			cli_die(EXIT_INPUT, "out of memory");
		ro.mark = mark;
		ro.nmark = marks(&o, m, i, mark);
		char label[64];
		movie_frame_label(&fr, i, label, sizeof label);
		ro.label = label;
		if (raster_mesh(img, m, &p, &ro, &err) != MESH_OK)
			cli_die(EXIT_INPUT, "frame %d: %s", i, err.msg);
		if (o.format != FMT_PPM)
			put(fd, img->rgb, 3 * (size_t)w * h);
		else if (movie_ppm_write(stdout, img) != MESH_OK)
			cli_write_error("stdout");
	}
	free(mark);
	if (o.format != FMT_PPM) {
		close(fd);
		cli_spawn_wait(o.ffmpeg, pid, errfd);
		if (isatty(2))
			fprintf(stderr, "%s: %s: %d frames, %d x %d, %.6g s at %d per second, tension scale %.3g\n",
		        cli_name, o.out, fr.n, w, h, (double)fr.n / o.fps, o.fps, scale);
	}
	raster_free(img);
	movie_frames_free(&fr);
	cli_finish();
}
