function [v, f] = read_obj(path)
% Vertices (n x 3) and triangles (m x 3, 1-based) of a Wavefront OBJ file.
% Reads 'v x y z' and 'f a b c' lines (a face corner may be 'a/t/n'); other
% lines are skipped.
text = fileread(path);
vt = regexp(text, '(?m)^v\s+(\S+)\s+(\S+)\s+(\S+)', 'tokens');
v = reshape(str2double([vt{:}]), 3, []).';
ft = regexp(text, '(?m)^f\s+(\d+)\S*\s+(\d+)\S*\s+(\d+)', 'tokens');
f = reshape(str2double([ft{:}]), 3, []).';
end
