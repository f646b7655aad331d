#!/usr/bin/perl
# layers.pl TOP OBJDIR: the dependency rules of libmesh, as TAP.
# The layers are the folders of libmesh/ in the order of the Makefile's
# LAYERS (bottom up).  Every source and header is a node; two kinds of use
# are read: quoted includes (of every .c, .cc and .h) and the symbols each
# object file takes from another (nm: undefined there, defined in the
# other; a call or a variable).  Checked: nothing uses a file of a higher
# layer, and no files use each other in a circle (a circle of includes, or
# of calls: two sources that call each other, directly or around).
use strict;
use warnings;

my ($top, $obj) = @ARGV;
die "usage: layers.pl TOP OBJDIR\n" unless defined $obj;
open my $mk, '<', "$top/Makefile" or die "layers.pl: $top/Makefile: $!\n";
my @layers;
while (<$mk>) { @layers = split ' ', $1 if /^LAYERS\s*=\s*(.*)$/; }
close $mk;
my %rank;
@rank{@layers} = 0 .. $#layers;

my (%layer, %file);  # node (file name) -> layer; -> its path
for my $l (@layers) {
	for my $f (glob "$top/libmesh/$l/*.{c,cc,h}") {
		(my $m = $f) =~ s{.*/}{};
		$layer{$m} = $l;
		$file{$m} = $f;
	}
}
my %uses;  # "a b" -> what a takes from b
my $n = 0;
my @fail;
sub use_edge {
	my ($a, $b, $what) = @_;
	return if $a eq $b;
	$uses{"$a $b"} //= $what;
}
for my $m (sort keys %file) {
	my $f = $file{$m};
	open my $in, '<', $f or die "layers.pl: $f: $!\n";
	while (<$in>) {
		next unless /^\s*#\s*include\s+"([^"]+)"/;
		my $inc = $1;
		(my $h = $inc) =~ s{.*/}{};
		if (!exists $layer{$h}) {
			push @fail, "$f includes \"$inc\", which is no header of libmesh";
			next;
		}
		use_edge($m, $h, "#include \"$inc\"");
	}
	close $in;
}
# symbols: defined where, used where
my (%def, %und);
for my $l (@layers) {
	for my $o (glob "$obj/$l/*.o") {
		(my $m = $o) =~ s{.*/}{};
		$m =~ s/\.o$//;
		$m = exists $layer{"$m.c"} ? "$m.c" : "$m.cc";
		# an object left by a source since renamed or removed
		next unless exists $layer{$m};
		open my $nm, '-|', 'nm', '-P', $o or die "layers.pl: nm $o: $!\n";
		while (<$nm>) {
			my ($sym, $type) = split ' ';
			next unless defined $type;
			if ($type eq 'U') { push @{ $und{$m} }, $sym; }
			elsif ($type =~ /^[TDRBVWC]$/) { $def{$sym} = $m; }
		}
		close $nm;
	}
}
my $nobj = keys %und;
for my $m (sort keys %und) {
	for my $s (@{ $und{$m} }) {
		use_edge($m, $def{$s}, "the symbol $s") if exists $def{$s};
	}
}
print "1..", 3, "\n";
# 1: files and objects were read
my @mods = sort keys %layer;
if (@mods && $nobj) {
	print "ok 1 - ", scalar(@mods), " files in ", scalar(@layers), " layers, $nobj objects read\n";
} else {
	print "not ok 1 - no modules or no objects under $obj\n";
}
# 2: no use runs upward
my @up;
for my $e (sort keys %uses) {
	my ($a, $b) = split ' ', $e;
	push @up, "$a ($layer{$a}) uses $b ($layer{$b}): $uses{$e}"
		if $rank{ $layer{$b} } > $rank{ $layer{$a} };
}
push @up, @fail;
if (@up) {
	print "not ok 2 - uses run upward\n";
	print "#   $_\n" for @up;
} else {
	print "ok 2 - every use runs down or within a layer (", scalar(keys %uses), " uses)\n";
}
# 3: no circle (depth-first search for a back edge)
my %adj;
for my $e (keys %uses) { my ($a, $b) = split ' ', $e; push @{ $adj{$a} }, $b; }
my (%state, @stack, @circle);
sub visit {
	my ($v) = @_;
	$state{$v} = 1;
	push @stack, $v;
	for my $w (sort @{ $adj{$v} // [] }) {
		if (($state{$w} // 0) == 1 && !@circle) {
			my $i = 0;
			$i++ while $stack[$i] ne $w;
			@circle = (@stack[$i .. $#stack], $w);
		} elsif (!$state{$w}) {
			visit($w);
		}
		last if @circle;
	}
	pop @stack;
	$state{$v} = 2;
}
for my $v (sort keys %layer) { visit($v) if !$state{$v} && !@circle; }
if (@circle) {
	print "not ok 3 - files use each other in a circle: ", join(' -> ', @circle), "\n";
	for my $i (0 .. $#circle - 1) {
		print "#   $circle[$i] -> $circle[$i + 1]: $uses{\"$circle[$i] $circle[$i + 1]\"}\n";
	}
} else {
	print "ok 3 - no circle between files\n";
}
