% Runs one case of the authors' reference code (exported outside this
% repository) under Octave and writes its output map in the input OBJ's
% vertex order, so that it can be measured exactly like demkit's.
%
%   octave-cli run_reference.m sdem  CODE MESH.obj POP OUT.obj
%   octave-cli run_reference.m torus CODE MESH.obj POP OUT.obj MAT R r
%   octave-cli run_reference.m param CODE MESH.obj area OUT.obj CUT R r
%   octave-cli run_reference.m edem  CODE MESH.obj POP OUT.obj A B C SELF
%   octave-cli run_reference.m edeq  CODE MESH.obj POP OUT.obj A0 B0 C0 SELF
%
% CODE: the root of the authors' SDEM or TDEM repository (the one with code/
% and data/). POP: a population file (one value per face) or 'area' (the
% input's face areas). MAT: the authors' .mat of a torus example, which holds
% the torus already sliced along its seam (v, f); it is checked against MESH
% and POP. CUT: the authors' cut path, 0-based vertex pairs. R, r: the target
% torus radii. A B C: the target ellipsoid's radii (edem), A0 B0 C0 the
% initial guess (edeq). SELF: 1 when the surface lies on the ellipsoid already
% and is its own initial map (the demos' first examples), 0 for the
% ellipsoidal conformal map as the initial map (their second examples).
%
% The time covers what the authors' demos run after loading a mesh, with
% tic/toc, file reading and writing excluded:
%   sdem:  spherical_conformal_map + mobius_area_correction_spherical
%          + SDEM(v, f, population, S, 0.1, 1e-3, 200)        (demo_SDEM.m)
%   torus: TDEM(v, f, population, R, r, 0.1, 1e-2, 500)       (demo_TDEM_torus.m)
%   param: slice_mesh along the cut + corners + rectangular_map_periodic2
%          + toroidal_projection + TDEM(map0, f, area, R, r, 0.1, 1e-2, 500)
%                                                     (demo_TDEM_parameterization.m)
%   edem:  [ellipsoidal_conformal_map unless SELF]
%          + EDEM(v, f, population, A, B, C, r0, 0.1, 1e-3, 300)  (demo_EDEM.m)
%   edeq:  [ellipsoidal_conformal_map unless SELF]
%          + EDEQ(v, f, population, 5, A0, B0, C0, r0, 0.1, 1e-5, 300, 5)
%                                                     (demo_EDEQ.m)
% For edeq the last line also gives the radii chosen: radii=A:B:C.
% Iterations are counted from the step lines the reference prints (they go
% to stdout as it runs, and through diary to a file parsed afterwards).
% Last line of stdout: REFERENCE time_s=... iterations=... init_s=... method_s=...

1;

function n = last_step(file)
% The largest N of the reference's "N        error" progress lines in file.
t = regexp(fileread(file), '(?m)^\s*(\d+)\s+\S+\s*$', 'tokens');
n = max([-1, cellfun(@(c) str2double(c{1}), t)]);
end

function p = read_population(spec, f, v)
if strcmp(spec, 'area')
  p = face_area(f, v);
else
  t = fileread(spec);
  t = regexprep(t, '#[^\n]*', '');
  p = sscanf(t, '%f');
end
if numel(p) ~= size(f, 1)
  error('population: %d values for %d faces', numel(p), size(f, 1));
end
p = p(:);
end

function parent = match_vertices(vs, vo)
% For every row of vs, the row of vo at the same position (within 1e-6).
parent = zeros(size(vs, 1), 1);
dist = zeros(size(vs, 1), 1);
for s = 1:500:size(vs, 1)
  k = s:min(s + 499, size(vs, 1));
  d2 = sum(vs(k, :) .^ 2, 2) + sum(vo .^ 2, 2).' - 2 * vs(k, :) * vo.';
  [dist(k), parent(k)] = min(d2, [], 2);
end
if max(sqrt(max(dist, 0))) > 1e-6
  error('the .mat vertices do not all lie on the OBJ''s vertices');
end
end

args = argv();
kind = args{1}; code = args{2}; mesh = args{3}; pop = args{4}; out = args{5};
here = fileparts(mfilename('fullpath'));
addpath(here);
if ~exist('fmincon') || ~exist('optimoptions') || ~exist('triangulation') || ~exist('vertexAttachments') ...
   || ~exist('scatteredInterpolant')
  addpath(fullfile(here, 'compat'));   % stand-ins for what Octave lacks
end
addpath(fullfile(code, 'code'));
% meshboundaries walks a boundary loop recursively, one call per vertex; Octave's
% default limit (256) is below the loops of the sliced models (MATLAB's is 500).
max_recursion_depth(10000);
[v_in, f_in] = read_obj(mesh);
init_s = NaN;
steps = [out '.steps'];   % the reference's printed steps
if exist(steps, 'file'), delete(steps); end
diary off;

switch kind
  case 'sdem'
    population = read_population(pop, f_in, v_in);
    t0 = tic;
    S1 = spherical_conformal_map(v_in, f_in);
    S = mobius_area_correction_spherical(v_in, f_in, S1);
    init_s = toc(t0);
    diary(steps); map = SDEM(v_in, f_in, population, S, 0.1, 1e-3, 200); diary off;
    time_s = toc(t0);
    map_in = map;

  case 'torus'
    [mat, R, r] = deal(args{6}, str2double(args{7}), str2double(args{8}));
    ex = load(mat);
    if abs(ex.R - R) > 1e-12 || abs(ex.r - r) > 1e-12
      error('radii %g:%g differ from the .mat''s %g:%g', R, r, ex.R, ex.r);
    end
    population = read_population(pop, f_in, v_in);
    rel = max(abs(population - ex.population(:)) ./ abs(ex.population(:)));
    if rel > 1e-9
      error('the population file differs from the .mat''s (relative %g)', rel);
    end
    parent = match_vertices(ex.v, v_in);
    if ~isequal(parent(ex.f), f_in)
      error('the .mat''s sliced faces are not the OBJ''s faces');
    end
    t0 = tic;
    diary(steps); [map, uv] = TDEM(ex.v, ex.f, population, R, r, 0.1, 1e-2, 500); diary off;
    time_s = toc(t0);
    map_in = zeros(size(v_in));
    map_in(parent, :) = map;

  case 'param'
    [cut, R, r] = deal(args{6}, str2double(args{7}), str2double(args{8}));
    t = regexprep(fileread(cut), '#[^\n]*', '');
    ee = reshape(sscanf(t, '%d'), 2, []).' + 1;
    t0 = tic;
    [f, v, parent] = slice_mesh(f_in, v_in, ee);
    % The four copies of the base point are the corners; order them along
    % the boundary loop, starting the loop at the first one.
    bd = meshboundaries(f);
    loop = bd{1};
    copies = find(parent == mode(parent));
    if numel(copies) ~= 4
      error('the cut does not meet itself at one base point (%d copies)', numel(copies));
    end
    [~, at] = ismember(copies, loop);
    corner = loop(sort(at));
    loop = loop([find(loop == corner(1)):end, 1:find(loop == corner(1)) - 1]);
    % The side from corner 1 to 2 becomes the one of length 2*pi*R: the longer.
    side = @(i, j) sum(sqrt(sum(diff(v(loop(find(loop == corner(i)):find(loop == corner(j))), :)) .^ 2, 2)));
    if side(1, 2) < side(2, 3)
      corner = corner([2; 3; 4; 1]);
    end
    uv0 = rectangular_map_periodic2(v, f, corner, 2 * pi * R, 2 * pi * r);
    map0 = toroidal_projection(uv0, R, r);
    population = face_area(f, v);
    init_s = toc(t0);
    diary(steps); [map, uv] = TDEM(map0, f, population, R, r, 0.1, 1e-2, 500); diary off;
    map_in = zeros(size(v_in));
    map_in(parent, :) = map;
    time_s = toc(t0);

  case {'edem', 'edeq'}
    radii = [str2double(args{6}), str2double(args{7}), str2double(args{8})];
    self = strcmp(args{9}, '1');
    population = read_population(pop, f_in, v_in);
    t0 = tic;
    if self
      r0 = v_in;
    else
      r0 = ellipsoidal_conformal_map(v_in, f_in, radii(1), radii(2), radii(3));
    end
    init_s = toc(t0);
    diary(steps);
    if strcmp(kind, 'edem')
      map = EDEM(v_in, f_in, population, radii(1), radii(2), radii(3), r0, 0.1, 1e-3, 300);
    else
      [map, ea, eb, ec] = EDEQ(v_in, f_in, population, 5, radii(1), radii(2), radii(3), r0, ...
                               0.1, 1e-5, 300, 5);
      chosen = [ea, eb, ec];
    end
    diary off;
    time_s = toc(t0);
    map_in = map;

  otherwise
    error('unknown case kind %s', kind);
end

write_obj(out, map_in, f_in);
extra = '';
if exist('chosen', 'var')
  extra = sprintf(' radii=%.6f:%.6f:%.6f', chosen);
end
printf('REFERENCE time_s=%.6f iterations=%d init_s=%.6f method_s=%.6f%s\n', ...
       time_s, last_step(steps), init_s, time_s - init_s, extra);
